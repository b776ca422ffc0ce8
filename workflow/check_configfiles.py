"""Before `workflow/regenerate.sh` starts Snakemake: check the raw text of
every config file its command line names (``--configfile A B``) and of every
profile it or the environment names (``--profile``, ``$SNAKEMAKE_PROFILE``,
``--workflow-profile``) with the config files those set (``configfile:``),
so that nothing in them is evaluated or expanded
(:func:`modal.thesis.config.profile_config_files`).

Snakemake loads ``--configfile`` files while it parses its command line,
before the Snakefile runs, and evaluates a file that sets ``__use_yte__:
true`` as a yte template (Python expressions in values starting with
``?``); it also expands YAML aliases there. The Snakefile refuses such a
config before any job (:func:`modal.thesis.config.check_config_files`), but
by then the template has run. Here it has not: the same check runs first.

Usage: ``python workflow/check_configfiles.py [snakemake arguments...]``.
Exit status: 0 (plain data), 2 (refused, one line on stderr).
"""

from __future__ import annotations

import sys

from modal.thesis.config import configfile_options, check_config_files


def main(argv) -> int:
    files = ["config/config.yaml", *(f for files in configfile_options(["snakemake", *argv]) for f in files)]
    try:
        check_config_files(files, ["snakemake", *argv])
    except (OSError, ValueError) as exc:
        print(f"refused before Snakemake starts: {exc}", file=sys.stderr)
        return 2
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
