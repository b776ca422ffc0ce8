# Report notebooks (papermill) and the reproduction report.


def report_outputs():
    return []
