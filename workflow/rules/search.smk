# Searches of the settings the thesis does not state (config `searches`,
# modal.thesis.search): one job per setting runs its study under each of the
# study's interpretations and scores it against the printed tables; one job
# gathers every search into results/searches/<search>.csv and the summary
# results/tables/searches.csv, which the reproduction summary cites.


rule search_setting:
    input:
        code=code_inputs("workflow/scripts/search_setting.py"),
        published=config["published"],
    output:
        res("searches/{search}/{setting}.csv"),
    log:
        res("logs/search_{search}_{setting}.log"),
    threads: 1
    resources:
        mem_mb=400,
        runtime=lambda w: identify_runtime(config["searches"][w.search]["study"]),
    params:
        code=code_hashes("workflow/scripts/search_setting.py"),
        sha256=content_hashes(config["published"]),
        setting=lambda w: search_settings(w.search)[w.setting],
        study=lambda w: config["searches"][w.search]["study"],
        interpretations=lambda w: {
            i: config["interpretations"][i]
            for i in config["studies"][config["searches"][w.search]["study"]][
                "interpretations"
            ]
        },
        tables=lambda w: {
            n: table_spec(n) for n in config["searches"][w.search]["tables"]
        },
        seeds=config["seeds"],
    script:
        "../scripts/search_setting.py"


rule searches:
    input:
        code=code_inputs("workflow/scripts/searches.py"),
        settings=[
            res(f"searches/{name}/{s}.csv")
            for name in SEARCHES
            for s in search_settings(name)
        ],
    output:
        searches=[res(f"searches/{name}.csv") for name in SEARCHES],
        summary=SEARCH_SUMMARY,
    log:
        res("logs/searches.log"),
    threads: 1
    resources:
        mem_mb=400,
        runtime=10,
    params:
        code=code_hashes("workflow/scripts/searches.py"),
        searches=config.get("searches", {}),
        settings={name: search_settings(name) for name in SEARCHES},
    script:
        "../scripts/searches.py"
