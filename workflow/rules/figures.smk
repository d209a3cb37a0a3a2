# Figures of the sweep (PNG), numbered after the source study, collected in the report.


rule figures:
    input:
        harmonics="results/tables/harmonics.csv",
        cases="results/tables/cases.csv",
        bands="results/tables/bands.csv",
        case_files=analysis_cases(),
        kurtograms=expand("results/bands/{case}_kurtogram.npz", case=CASES),
        spectra=expand("results/spectra/{case}.npz", case=CASES),
        code=script_code("figures.py"),
    output:
        report(
            directory("results/figures"),
            patterns=["{name}.png"],
            caption="../report/figures.rst",
            category="Figures",
        ),
    params:
        analysis=analysis_params,
        example=example_cases,
    log:
        "logs/figures.log",
    benchmark:
        "logs/benchmarks/figures.tsv"
    conda:
        ENV
    threads: 1
    resources:
        mem_mb=3000,
        runtime=15,
    script:
        "../scripts/figures.py"
