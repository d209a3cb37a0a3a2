"""The docs stay a reference: README short and runnable, no heading named after an issue, a
session or a date, every benchmark command a docs page gives runs a registered benchmark."""
import re
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

import benchmarks  # noqa: E402

PAGES = [ROOT / "README.md", *sorted((ROOT / "docs").glob("*.md"))]
DATED = re.compile(r"\bissue\s+\d+|\bsession\b|\b20\d\d-\d\d-\d\d\b|\bpart\s+\d+\b", re.I)


def test_readme_is_short_and_starts_with_the_two_commands():
    text = (ROOT / "README.md").read_text(encoding="utf-8")
    assert len(text.splitlines()) <= 250
    block = re.search(r"```bash\n(.*?)```", text, re.S).group(1)
    commands = [line for line in block.splitlines() if line.strip()]
    assert len(commands) == 2
    assert commands[0].endswith("snakemake -j2") and "pytest" in commands[1]


def test_readme_has_no_date_and_no_path_outside_the_repository():
    text = (ROOT / "README.md").read_text(encoding="utf-8")
    assert not re.search(r"\b20\d\d-\d\d-\d\d\b", text)
    assert "../" not in text


def test_no_heading_is_named_after_an_issue_a_session_or_a_date():
    dated = [f"{page.name}: {line}" for page in PAGES
             for line in page.read_text(encoding="utf-8").splitlines()
             if line.startswith("#") and DATED.search(line)]
    assert dated == []


def test_every_benchmark_command_in_the_docs_is_registered():
    names = {m.group(1) for page in [*PAGES, ROOT / "CHANGELOG.md"]
             for m in re.finditer(r"python -m benchmarks (\w+)", page.read_text(encoding="utf-8"))}
    assert names and names <= set(benchmarks.REGISTRY) | {"NAME"}
