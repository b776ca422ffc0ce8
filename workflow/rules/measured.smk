# Measured records (config "measured"): modes and stabilisation diagram of
# each, as `modal identify` makes them.


rule measured_identify:
    input:
        code=code_inputs("workflow/scripts/measured.py"),
        record=lambda w: config["measured"][w.name]["path"],
    output:
        modes=res("measured/{name}/modes.csv"),
        poles=res("measured/{name}/poles.csv"),
        diagram=report(
            res("measured/{name}/stabilisation.png"), category="Measured records"
        ),
    log:
        res("logs/measured_{name}.log"),
    benchmark:
        res("benchmarks/measured_{name}.tsv")
    threads: 1
    resources:
        mem_mb=1000,
        runtime=10,
    params:
        spec=lambda w: config["measured"][w.name],
        sha256=lambda w: content_hashes(config["measured"][w.name]["path"]),
    script:
        "../scripts/measured.py"
