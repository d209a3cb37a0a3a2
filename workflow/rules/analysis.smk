# Per-case analysis: demodulation bands (kurtogram + fixed) and envelope harmonics.
# Analysis settings reach the jobs through params, so changing them reruns these jobs only.


rule bands:
    input:
        case=analysis_case,
        code=script_code("bands.py"),
        rebuilt=lambda w: marker_if_present(rebuild_marker(ANALYSIS_STAGE, w.case)),
    output:
        bands="results/bands/{case}.json",
        kurtogram="results/bands/{case}_kurtogram.npz",
    params:
        analysis=analysis_params,
    log:
        "logs/bands/{case}.log",
    benchmark:
        "logs/benchmarks/bands/{case}.tsv"
    conda:
        ENV
    threads: 1
    resources:
        mem_mb=1500,
        runtime=10,
    script:
        "../scripts/bands.py"


rule envelope:
    input:
        case=analysis_case,
        bands="results/bands/{case}.json",
        code=script_code("envelope.py"),
    output:
        harmonics="results/harmonics/{case}.csv",
        spectra="results/spectra/{case}.npz",
    params:
        analysis=analysis_params,
    log:
        "logs/envelope/{case}.log",
    benchmark:
        "logs/benchmarks/envelope/{case}.tsv"
    conda:
        ENV
    threads: 1
    resources:
        mem_mb=1500,
        runtime=10,
    script:
        "../scripts/envelope.py"
