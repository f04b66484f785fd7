# SPDX-License-Identifier: AGPL-3.0-or-later
"""The README's Python section: every ```python block runs as written, from
the repository root (its outputs go to a scratch folder)."""
import os
import re

import palpa

SOURCE = os.environ.get("PALPA_SOURCE_DIR", os.path.join(os.path.dirname(__file__), "..", ".."))


def python_blocks():
    with open(os.path.join(SOURCE, "README.md")) as f:
        readme = f.read()
    section = readme[readme.index("\n## Python\n"):]
    section = section[:section.index("\n## ", 1)]
    return re.findall(r"```python\n(.*?)```", section, re.S)


def test_every_python_block_of_the_readme_runs(tmp_path, monkeypatch):
    blocks = python_blocks()
    assert blocks, "the README's Python section has no python block"
    os.symlink(os.path.abspath(os.path.join(SOURCE, "examples")), tmp_path / "examples")
    monkeypatch.chdir(tmp_path)
    palpa.set_log_level("warning")
    try:
        for block in blocks:
            exec(compile(block, "README.md (python block)", "exec"), {})
    finally:
        palpa.set_log_level("info")
    assert (tmp_path / "fit-ecoflex" / "material.json").exists()
    assert (tmp_path / "foot.ply").exists()
