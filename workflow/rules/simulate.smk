# One contact-history job per load x depth case -> one HDF5 file per case.


rule simulate:
    input:
        code=script_code("simulate.py"),
        profile=profile_files(SETTINGS),
    output:
        "results/cases/{case}.h5",
    params:
        simulation=simulation_params,
    log:
        "logs/simulate/{case}.log",
    benchmark:
        "logs/benchmarks/simulate/{case}.tsv"
    conda:
        ENV
    threads: 1
    resources:
        mem_mb=2000,
        runtime=20,
    script:
        "../scripts/simulate.py"
