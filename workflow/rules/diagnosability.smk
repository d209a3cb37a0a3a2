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
        sensor=sensor_params,
        analysis=analysis_params,
        snr_db=list(SETTINGS.diagnosability.snr_db),
        kurtogram_from=SETTINGS.diagnosability.kurtogram_from,
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


rule false_alarms:
    input:
        case="results/cases/{case}.h5",
        reference=reference_case,
        code=SIGNAL_CODE + SENSOR_CODE,
    output:
        "results/false_alarms/{case}.csv",
    params:
        sensor=sensor_params,
        analysis=analysis_params,
        snr_db=list(SETTINGS.diagnosability.snr_db),
        n_trials=SETTINGS.diagnosability.false_alarm_trials,
        kurtogram_from=SETTINGS.diagnosability.kurtogram_from,
    log:
        "logs/false_alarms/{case}.log",
    benchmark:
        "logs/benchmarks/false_alarms/{case}.tsv"
    conda:
        ENV
    threads: 1
    resources:
        mem_mb=1500,
        runtime=30,
    script:
        "../scripts/false_alarms.py"


rule diagnosability:
    input:
        cells=expand("results/diagnosability/{case}.csv", case=CASES),
        false_alarms=expand("results/false_alarms/{case}.csv", case=HEALTHY),
    output:
        table=report(
            "results/tables/diagnosability.csv",
            caption="../report/diagnosability.rst",
            category="Diagnosability",
        ),
        false_alarms=report(
            "results/tables/false_alarms.csv",
            caption="../report/false_alarms.rst",
            category="Diagnosability",
        ),
        pages=report(
            directory("results/tables_html_diagnosability"),
            patterns=["{name}.html"],
            caption="../report/diagnosability.rst",
            category="Diagnosability",
        ),
        maps=report(
            directory("results/figures_diagnosability"),
            patterns=["{name}.png"],
            caption="../report/diagnosability.rst",
            category="Diagnosability",
        ),
    params:
        cases=CASE_IDS,
    log:
        "logs/diagnosability.log",
    benchmark:
        "logs/benchmarks/diagnosability.tsv"
    conda:
        ENV
    threads: 1
    resources:
        mem_mb=1000,
        runtime=5,
    script:
        "../scripts/diagnosability.py"
