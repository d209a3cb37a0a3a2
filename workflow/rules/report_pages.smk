# Pages of the report that are read in place: every table as HTML (the CSVs stay downloadable)
# and the "study vs this model" page (bearing_envelope.study.paper.compare), regenerated from the
# sweep's tables whenever they change (paper_run_tables: common.smk).


rule report_tables:
    input:
        cases="results/tables/cases.csv",
        bands="results/tables/bands.csv",
        harmonics="results/tables/harmonics.csv",
        pivots="results/tables/pivots",
        code=script_code("report_tables.py"),
    output:
        report(
            directory("results/tables_html"),
            patterns=["{name}.html"],
            caption="../report/tables_html.rst",
            category="Tables",
            labels={"table": "{name}"},
        ),
    log:
        "logs/report_tables.log",
    benchmark:
        "logs/benchmarks/report_tables.tsv"
    conda:
        ENV
    threads: 1
    resources:
        mem_mb=1000,
        runtime=5,
    script:
        "../scripts/report_tables.py"


rule paper:
    input:
        unpack(lambda w: {f"paper_{k}": v for k, v in paper_run_tables().items()}),
        cases="results/tables/cases.csv",
        bands="results/tables/bands.csv",
        harmonics="results/tables/harmonics.csv",
        code=script_code("paper.py"),
    output:
        md="results/paper/paper.md",
        html=report(
            "results/paper/paper.html",
            caption="../report/paper.rst",
            category="Study vs this model",
            labels={"page": "findings of Brusa et al. 2021 and this model's numbers"},
        ),
    log:
        "logs/paper.log",
    benchmark:
        "logs/benchmarks/paper.tsv"
    conda:
        ENV
    threads: 1
    resources:
        mem_mb=1000,
        runtime=5,
    script:
        "../scripts/paper.py"
