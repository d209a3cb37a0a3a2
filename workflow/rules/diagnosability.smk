# Optional stage after the simulation: contact history -> synthetic accelerometer signal
# (modes, noise at each SNR, tones) -> envelope chain per band -> is BPFI detected?


rule diagnose:
    input:
        case="results/cases/{case}.h5",
        reference=reference_case,
        code=SIGNAL_CODE + SENSOR_CODE,
    output:
        "results/diagnosability/{case}.csv",
    params:
        sensor=lambda w: json.dumps(config.get("sensor", {}), sort_keys=True),
        analysis=analysis_params,
        snr_db=lambda w: config.get("diagnosability", {}).get("snr_db", [20, 10, 0, -10, -20]),
    log:
        "logs/diagnose/{case}.log",
    benchmark:
        "logs/benchmarks/diagnose/{case}.tsv"
    conda:
        ENV
    threads: 1
    resources:
        mem_mb=1500,
        runtime=10,
    script:
        "../scripts/diagnose.py"


rule diagnosability:
    input:
        expand("results/diagnosability/{case}.csv", case=CASES),
    output:
        table=report(
            "results/tables/diagnosability.csv",
            caption="../report/diagnosability.rst",
            category="Diagnosability",
        ),
        maps=report(
            directory("results/figures_diagnosability"),
            patterns=["{name}.png"],
            caption="../report/diagnosability.rst",
            category="Diagnosability",
        ),
    log:
        "logs/diagnosability.log",
    conda:
        ENV
    threads: 1
    resources:
        mem_mb=1000,
        runtime=5,
    script:
        "../scripts/diagnosability.py"
