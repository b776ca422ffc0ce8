# Measured records (config "measured"): modes and stabilisation diagram of
# each, as `modal identify` makes them; an entry with `setups` is a roving
# test, its setups merged into one set of modes drawn on its geometry.


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
    wildcard_constraints:
        name=names_regex(measured_names("path")),
    threads: 1
    resources:
        mem_mb=1000,
        runtime=10,
    params:
        code=code_hashes("workflow/scripts/measured.py"),
        spec=lambda w: config["measured"][w.name],
        sha256=lambda w: content_hashes(config["measured"][w.name]["path"]),
    script:
        "../scripts/measured.py"


rule measured_setups:
    input:
        code=code_inputs("workflow/scripts/measured_setups.py"),
        files=lambda w: setup_files(config["measured"][w.name]),
    output:
        modes=res("measured/{name}/modes.csv"),
        shapes=res("measured/{name}/shapes.csv"),
        pictures=report(res("measured/{name}/modes.png"), category="Measured records"),
    log:
        res("logs/measured_{name}.log"),
    benchmark:
        res("benchmarks/measured_{name}.tsv")
    wildcard_constraints:
        name=names_regex(measured_names("setups")),
    threads: 1
    resources:
        mem_mb=1000,
        runtime=10,
    params:
        code=code_hashes("workflow/scripts/measured_setups.py"),
        spec=lambda w: config["measured"][w.name],
        sha256=lambda w: content_hashes(*setup_files(config["measured"][w.name])),
    script:
        "../scripts/measured_setups.py"
