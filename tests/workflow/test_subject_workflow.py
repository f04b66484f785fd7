# SPDX-License-Identifier: AGPL-3.0-or-later
"""The subject pipeline end to end on the bundled synthetic subject, at a small
size (examples/subject/subject-small.json: four of its eight locations, a
coarser body): every location's fitted small-strain
Young's modulus within 5% of the truth the logs were made from (CalculiX,
examples/subject/truth.json), every layer depth within 1 mm (two measured by
ultrasound, two searched by the fit), the designed chair lowers the score by
more than half (re-solved from scratch), and the report loads in a browser."""

import json
import os
import pathlib
import subprocess

PALPA = os.environ["PALPA_BINARY"]
SOURCE = pathlib.Path(os.environ["PALPA_SOURCE_DIR"])
SUBJECTS = SOURCE / "examples" / "subject"


def snakemake(subjects, out, *extra):
    return subprocess.run(["snakemake", "-s", str(SOURCE / "workflow" / "Snakefile"), "--cores", "2",
                           "--config", "subjects=%s" % subjects, "out=%s" % out, "palpa=%s" % PALPA,
                           "--keep-going", *extra],
                          cwd=out.parent, capture_output=True, text=True)


def test_small_subject_recovers_the_truth_and_designs_its_chair(tmp_path):
    out = tmp_path / "results"
    run = snakemake(SUBJECTS / "subject-small.json", out)
    assert run.returncode == 0, run.stderr[-4000:]
    results = out / "seated-small"
    fields = json.loads((results / "body" / "fields.json").read_text())
    truth = {l["name"]: l for l in json.loads((SUBJECTS / "truth.json").read_text())["locations"]}
    assert len(fields["locations"]) == 4
    searched = 0
    for l in fields["locations"]:
        t = truth[l["name"]]
        assert abs(l["youngs_modulus_Pa"] / t["youngs_modulus_Pa"] - 1.0) < 0.05, (l, t["youngs_modulus_Pa"])
        assert abs(l["depth_m"] - t["depth_m"]) < 1e-3, (l, t["depth_m"])
        searched += l["depth"] == "searched by the fit"
    assert searched == 2
    design = json.loads((results / "design" / "summary.json").read_text())
    assert design["zeta_reduction_percent"] > 50.0, design["zeta_reduction_percent"]
    # The body carried the fits: the moduli over its tets span the locations'.
    rest = json.loads((results / "rest" / "summary.json").read_text())
    moduli = [l["youngs_modulus_Pa"] for l in fields["locations"]]
    assert rest["body"]["youngs_modulus_Pa"]["min"] >= 0.99 * min(moduli)
    assert rest["body"]["youngs_modulus_Pa"]["max"] <= 1.01 * max(moduli)
    assert rest["body"]["youngs_modulus_Pa"]["max"] > 1.5 * rest["body"]["youngs_modulus_Pa"]["min"]
    # The report: every step's pictures, opened in a browser.
    html = (results / "report.html").read_text()
    for part in ("thigh-mid-left: measured and fitted curves", "the soft layer's depth over the skin",
                 "<td>designed support</td>", "searched by the fit"):
        assert part in html, part
    assert "not made" not in html
    page = subprocess.run(["/usr/bin/python3", str(SOURCE / "tests" / "browser" / "check_page.py"),
                           str(results / "report.html")], capture_output=True, text=True)
    assert page.returncode == 0, page.stdout + page.stderr
