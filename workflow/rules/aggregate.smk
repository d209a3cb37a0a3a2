# Sweep-level tables: tidy harmonics, per-case summary and load x depth pivots.


rule aggregate:
    input:
        harmonics=expand("results/harmonics/{case}.csv", case=CASES),
        bands=expand("results/bands/{case}.json", case=CASES),
        cases=expand("results/cases/{case}.h5", case=CASES),
        code=script_code("aggregate.py"),
        rebuilt=lambda w: [m for c in CASES for m in marker_if_present(rebuild_marker("harmonics", c))],
    output:
        harmonics=report(
            "results/tables/harmonics.csv",
            caption="../report/harmonics.rst",
            category="Tables",
        ),
        cases=report(
            "results/tables/cases.csv", caption="../report/cases.rst", category="Tables"
        ),
        bands=report(
            "results/tables/bands.csv", caption="../report/bands.rst", category="Tables"
        ),
        pivots=report(
            directory("results/tables/pivots"),
            patterns=["{name}.csv"],
            caption="../report/pivots.rst",
            category="Pivot tables",
        ),
    params:
        cases=CASE_IDS,
    log:
        "logs/aggregate.log",
    benchmark:
        "logs/benchmarks/aggregate.tsv"
    conda:
        ENV
    threads: 1
    resources:
        mem_mb=2000,
        runtime=10,
    script:
        "../scripts/aggregate.py"
