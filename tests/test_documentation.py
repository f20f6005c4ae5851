"""The README and docs/ hold what is true of the code: every ```python block runs (each on its own, in an empty
folder), the README stays a five-minute read, and the prose names no dates or commits (measured results live
in docs/results/, generated with their run record)."""

import re
from pathlib import Path

import pytest

REPO = Path(__file__).resolve().parents[1]
DOCUMENTS = [REPO / "README.md", *sorted((REPO / "docs").glob("**/*.md"))]
PYTHON_BLOCK = re.compile(r"^```python[ \t]*\n(.*?)^```", re.DOTALL | re.MULTILINE)
SLOW_MARK = "<!-- test: slow -->"  # on the line before a block that trains a model


def python_blocks(markdown: str) -> list[tuple[int, str, bool]]:
    """``(line number, code, slow)`` of each ```python block of a markdown text; slow when the line before the
    fence is :data:`SLOW_MARK`."""
    blocks = []
    for match in PYTHON_BLOCK.finditer(markdown):
        before = markdown[:match.start()].rstrip("\n").rsplit("\n", 1)[-1]
        blocks.append((markdown.count("\n", 0, match.start()) + 1, match.group(1), before.strip() == SLOW_MARK))
    return blocks


def _snippets():
    for doc in DOCUMENTS:
        for line, code, slow in python_blocks(doc.read_text()):
            name = f"{doc.relative_to(REPO)}:{line}"
            yield pytest.param(name, code, id=name, marks=[pytest.mark.smoke] if slow else [])


SNIPPETS = list(_snippets())


def test_python_blocks_are_found_with_their_line_and_slow_mark():
    text = f"# t\n\n```python\nx = 1\n```\n\n{SLOW_MARK}\n```python\ny = 2\n```\n\n```bash\nls\n```\n"
    assert python_blocks(text) == [(3, "x = 1\n", False), (8, "y = 2\n", True)]


def test_the_readme_and_every_paper_page_hold_python_that_is_run():
    documents = {param.values[0].split(":")[0] for param in SNIPPETS}
    assert {"README.md", "docs/actor.md", "docs/odmo.md", "docs/actformer.md", "docs/data.md"} <= documents


@pytest.mark.parametrize("name, code", SNIPPETS)
def test_documented_snippet_runs(name, code, tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)  # snippets write (runs/, out/) where they stand
    exec(compile(code, name, "exec"), {"__name__": "__snippet__"})


def test_the_readme_is_a_five_minute_read_with_the_suite_commands():
    text = (REPO / "README.md").read_text()
    assert len(text.splitlines()) <= 250
    assert "<!-- suite times: measured with the two commands above" in text
    assert re.search(r"unit tier takes about \d+ minutes and the whole suite about \d+", text)
    assert re.search(r"^python -m pytest +#", text, re.MULTILINE)  # the whole suite
    assert re.search(r'^python -m pytest -m "not smoke and not integration" +#', text, re.MULTILINE)


@pytest.mark.parametrize("doc", [d for d in DOCUMENTS if "results" not in d.relative_to(REPO).parts],
                         ids=lambda d: str(d.relative_to(REPO)))
def test_prose_names_no_dates_commits_or_issues(doc):
    text = doc.read_text()
    assert not re.search(r"\b20\d\d-\d\d-\d\d\b", text), "a date"
    assert not re.search(r"\b(?=[0-9a-f]*[a-f])(?=[0-9a-f]*\d)[0-9a-f]{7,40}\b", text), "a commit hash"
    assert not re.search(r"\bthe issue\b|\bissue's\b", text, re.IGNORECASE), "a reference to an issue"
