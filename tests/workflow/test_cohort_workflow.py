# SPDX-License-Identifier: AGPL-3.0-or-later
"""The workflow's bookkeeping on a cohort of three tiny subjects
(examples/subject/cohort): run with --cores 2, a rerun does nothing,
deleting one location's fit reruns only what depends on it (that fit, that
subject's body, rest, design and report, and the cohort's one support), a
run killed midway finishes when rerun, and the one support for all three
lowers every body's score at a price of under 25% against their own
designs."""

import json
import os
import pathlib
import re
import signal
import subprocess
import time

PALPA = os.environ["PALPA_BINARY"]
SOURCE = pathlib.Path(os.environ["PALPA_SOURCE_DIR"])
COHORT = SOURCE / "examples" / "subject" / "cohort" / "cohort.json"


def command(out, *extra):
    return ["snakemake", "-s", str(SOURCE / "workflow" / "Snakefile"), "--cores", "2", "--config",
            "subjects=%s" % COHORT, "out=%s" % out, "palpa=%s" % PALPA, *extra]


def snakemake(out, *extra):
    return subprocess.run(command(out, *extra), cwd=out.parent, capture_output=True, text=True)


def planned_jobs(out):
    """The jobs a run would do now: {rule: count} from a dry run's job table."""
    dry = snakemake(out, "--dry-run")
    assert dry.returncode == 0, dry.stderr[-3000:]
    text = dry.stdout + dry.stderr
    if "Nothing to be done" in text:
        return {}
    table = text[text.index("job "):]
    jobs = {}
    for line in table.splitlines()[2:]:
        m = re.match(r"^(\w+)\s+(\d+)", line)
        if not m:
            break
        if m.group(1) != "total":
            jobs[m.group(1)] = int(m.group(2))
    return jobs


def test_a_cohort_runs_once_and_reruns_only_what_changed(tmp_path):
    out = tmp_path / "results"
    # Killed midway (the whole process group, as a scheduler would), then rerun.
    first = subprocess.Popen(command(out), cwd=tmp_path, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL,
                             start_new_session=True)
    deadline = time.time() + 120
    while time.time() < deadline and not list(out.glob("*/fits/*/material.json")):
        time.sleep(0.5)
    os.killpg(first.pid, signal.SIGKILL)
    first.wait()
    assert snakemake(out, "--unlock").returncode == 0
    run = snakemake(out, "--rerun-incomplete")
    assert run.returncode == 0, run.stderr[-4000:]
    for name in ("tiny-a", "tiny-b", "tiny-c"):
        assert (out / name / "report.html").is_file(), name
        fields = json.loads((out / name / "body" / "fields.json").read_text())
        assert fields["locations"][0]["name"] == "underside"
    # One support for the three: every body's ζ_body lower than on the flat
    # seat, and the cohort's mean within 25% of the mean of the bodies' own
    # designs, every figure re-solved from scratch.
    cohort = json.loads((out / "cohort.design" / "summary.json").read_text())
    assert [b["name"] for b in cohort["bodies"]] == ["tiny-a", "tiny-b", "tiny-c"]
    assert cohort["every_body_lower"]
    assert all(b["zeta_body_ratio"] < 0.9 for b in cohort["bodies"]), cohort["bodies"]
    assert cohort["own_designs"]["price_of_one_support"] < 1.25, cohort["own_designs"]
    # Begun on the negative image of the average body, it beats it on the mean.
    assert cohort["cohort"]["start"] == "negative image of the average body"
    assert not cohort["worse_than_baseline_on_mean"], cohort["baseline"]
    assert "one support for the 3 subjects" in run.stdout + run.stderr

    # Up to date: nothing to do.
    assert planned_jobs(out) == {}
    # One fit deleted: that fit and what depends on it, nothing else.
    (out / "tiny-b" / "fits" / "underside" / "material.json").unlink()
    assert planned_jobs(out) == {"all": 1, "fit": 1, "body": 1, "rest": 1, "design": 1, "report": 1,
                                 "cohort_scene": 1, "cohort_design": 1}
    before = {p: p.stat().st_mtime_ns for p in out.glob("tiny-[ac]/**/*") if p.is_file()}
    run = snakemake(out)
    assert run.returncode == 0, run.stderr[-4000:]
    assert planned_jobs(out) == {}
    after = {p: p.stat().st_mtime_ns for p in before}
    assert before == after, "the other subjects' files changed"
