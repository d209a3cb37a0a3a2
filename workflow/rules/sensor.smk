# Synthetic accelerometer signal of each case (transfer path + noise + tones of the `sensor:`
# section), built only when `analysis.signal: acceleration` asks the analysis to run on it.


rule sensor:
    input:
        case="results/cases/{case}.h5",
        reference=reference_case,
        code=script_code("sensor.py"),
        rebuilt=lambda w: marker_if_present(rebuild_marker("cases", w.case)),
    output:
        "results/sensor/{case}.h5",
    params:
        sensor=sensor_params,
    log:
        "logs/sensor/{case}.log",
    benchmark:
        "logs/benchmarks/sensor/{case}.tsv"
    conda:
        ENV
    threads: 1
    resources:
        mem_mb=1500,
        runtime=10,
    script:
        "../scripts/sensor.py"
