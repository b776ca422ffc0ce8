# Measured records (config "measured"): modes and stabilisation diagram of
# each, as `modal identify` makes them.


rule measured_identify:
    input:
        ENGINE,
        record=lambda w: config["measured"][w.name]["path"],
    output:
        modes="results/measured/{name}/modes.csv",
        poles="results/measured/{name}/poles.csv",
        diagram=report("results/measured/{name}/stabilisation.png", category="Measured records"),
    params:
        spec=lambda w: config["measured"][w.name],
    log:
        "results/logs/measured_{name}.log",
    benchmark:
        "results/benchmarks/measured_{name}.tsv"
    script:
        "../scripts/measured.py"
