# Speed-accuracy trade of the fidelity knobs (issue 6): one knob at a time around the base
# fidelity, cost and error against a converged reference, Pareto front. Run by hand:
# `snakemake -j1 tradeoff` (not part of `all`; configured by the optional `tradeoff:` section).


rule tradeoff:
    input:
        code=script_code("tradeoff.py"),
    output:
        table=report(
            "results/tradeoff/tradeoff.csv",
            category="Speed-accuracy trade",
            labels={"what": "tidy table: case x knob value x metric"},
        ),
        pareto="results/tradeoff/pareto.csv",
        plot=report(
            "results/tradeoff/tradeoff.png",
            category="Speed-accuracy trade",
            labels={"what": "error vs CPU time per case, Pareto front"},
        ),
    params:
        # the study's section, the scene and the typed analysis, validated, as canonical JSON
        # (a change reruns the study) carrying them typed (study.job_transport.TradeoffSetup)
        tradeoff=lambda w: SETTINGS.tradeoff_param(),
    log:
        "logs/tradeoff.log",
    benchmark:
        "logs/benchmarks/tradeoff.tsv"
    conda:
        ENV
    threads: 1
    resources:
        mem_mb=3000,
        runtime=120,
    script:
        "../scripts/tradeoff.py"
