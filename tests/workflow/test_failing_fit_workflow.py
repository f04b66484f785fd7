# SPDX-License-Identifier: AGPL-3.0-or-later
"""A cohort where one location's fit fails: a subject whose 3 mm poke at one
location was recorded with the gauge wired backwards (every force negative),
beside a subject that is fine. With --keep-going the run ends non-zero, names
the subject, the location, the step and palpa's message with its file, and
finishes everything that does not depend on the failed fit: the other
location's fit, and the other subject's whole pipeline to its report. The
folders have spaces in their names."""

import json
import os
import pathlib
import subprocess

PALPA = os.environ["PALPA_BINARY"]
SOURCE = pathlib.Path(os.environ["PALPA_SOURCE_DIR"])
TINY = SOURCE / "examples" / "subject" / "cohort" / "tiny-a" / "subject.json"


def broken_subject(folder):
    """tiny-a's subject with absolute paths, plus a location 'flipped' whose
    only poke is a ready curve of negative forces."""
    s = json.loads(TINY.read_text())

    def absolute(p):
        return str((TINY.parent / p).resolve())

    underside = s["locations"][0]
    for p in underside["pokes"]:
        for key in ("force", "laser", "calibration"):
            p[key] = absolute(p[key])
    underside["ultrasound"]["force"] = absolute(underside["ultrasound"]["force"])
    for i in underside["ultrasound"]["interfaces"]:
        i["picks"] = absolute(i["picks"])
    flipped = json.loads(json.dumps(underside))
    flipped["name"] = "flipped"
    flipped["pokes"] = [{"radius": "3 mm", "curve": "flipped.csv"}]
    s["locations"].append(flipped)
    s["name"] = "broken"
    s["design"] = absolute(s["design"])
    folder.mkdir(parents=True)
    (folder / "subject.json").write_text(json.dumps(s, indent=1))
    rows = ["indentation_mm,force_N"] + [f"{0.1 * i:.1f},{-0.05 * i * i:.4f}" for i in range(16)]
    (folder / "flipped.csv").write_text("\n".join(rows) + "\n")
    return folder / "subject.json"


def test_one_failed_fit_is_named_and_the_rest_finishes(tmp_path):
    broken = broken_subject(tmp_path / "broken subject")
    cohort = tmp_path / "cohort.json"
    cohort.write_text(json.dumps({"palpa_cohort": 1, "subjects": [str(TINY), str(broken)]}))
    out = tmp_path / "results with space"
    run = subprocess.run(["snakemake", "-s", str(SOURCE / "workflow" / "Snakefile"), "--cores", "2", "--keep-going",
                          "--config", f"subjects={cohort}", f"out={out}", f"palpa={PALPA}"],
                         cwd=tmp_path, capture_output=True, text=True)
    said = run.stdout + run.stderr
    assert run.returncode != 0, said[-3000:]
    # The failure: subject, location, step, palpa's message naming the curve and its column.
    line = next((x for x in said.splitlines() if x.startswith("palpa workflow: subject broken")), None)
    assert line is not None, said[-3000:]
    assert "location flipped: fit failed:" in line, line
    assert "flipped/r3mm.csv:" in line and "column 'force_N'" in line and "is negative" in line, line
    assert str(out / "broken" / "logs" / "fit-flipped.log") in said
    assert "1 step(s) failed" in said
    # Only that step failed, and what depends on it did not run.
    assert sum(x.startswith("palpa workflow: subject ") for x in said.splitlines()) == 1, said[-3000:]
    assert not (out / "broken" / "fits" / "flipped" / "material.json").exists()
    assert not (out / "broken" / "body").exists()
    assert not (out / "broken" / "report.html").exists()
    # Everything else finished.
    assert (out / "broken" / "fits" / "underside" / "material.json").is_file()
    assert (out / "tiny-a" / "report.html").is_file()
    assert f"the report of subject tiny-a is {(out / 'tiny-a' / 'report.html').resolve()}" in said
