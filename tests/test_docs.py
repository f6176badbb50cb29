"""The documentation as users read it (issue 29).

A short README that starts with the demo, one section per system and a page for each
under docs/; every link between them resolving, as GitHub and HACS render them: a
relative link to a file that moved, or to the anchor of a renamed heading, is dead
there. The checkers return problems in words, as scripts/checks' do, and
the test_checker_* tests feed them small bad pages, to show each rule can fail.
"""

from collections import Counter
from collections.abc import Iterable, Iterator
import json
from pathlib import Path
import re
import tomllib
from typing import Final
import unicodedata

import yaml

REPO: Final = Path(__file__).parent.parent
README: Final = REPO / "README.md"
TRANSLATIONS: Final = REPO / "custom_components" / "tecoapi" / "translations"
EN_JSON: Final = TRANSLATIONS / "en.json"
MANIFEST: Final = REPO / "custom_components" / "tecoapi" / "manifest.json"
DEMO_DASHBOARD: Final = REPO / "tests" / "e2e" / "demo_dashboard.yaml"
# Where a text leads the user to the integration's own page or row: what follows
# the arrow is what Home Assistant shows there.
TO_THE_INTEGRATION: Final = re.compile(
    r"(?:Devices & services|Add integration|Zařízení a služby|Přidat integraci)"
    r"\*?\s*→\s*\*?"
)
OTHER_PARTS: Final = ("Add integration", "Přidat integraci", "Discovered")
"""What else of *Devices & services* a text may lead to."""
MAX_LINES: Final = 400

FENCE: Final = re.compile(r"^```.*?^```", re.MULTILINE | re.DOTALL)
CODE_SPAN: Final = re.compile(r"`[^`\n]*`")
LINK: Final = re.compile(r"\]\(([^()\s]+)\)")
HEADING: Final = re.compile(r"^(#{1,6}) (.+)$", re.MULTILINE)
EXTERNAL: Final = ("http://", "https://", "mailto:")

# Each system's section of the README: its page under docs/.
SYSTEMS: Final = {
    "Tecomat (TecoApi, PLCComS)": "docs/tecomat.md",
    "Mervis (Unipi)": "docs/mervis.md",
    "Panasonic FP (FP-I4C gateway)": "docs/fpi4c.md",
    "Tekon (ASUD.SCADA OPC-HTTP gateway)": "docs/tekon.md",
}


def pages() -> list[Path]:
    """The Markdown a user or a developer reads: the README, docs/, the READMEs."""
    return sorted(
        {README, *(REPO / "docs").glob("**/*.md")}
        | set((REPO / "tests").glob("**/README.md"))
        | set((REPO / "custom_components").glob("**/README.md"))
    )


def prose(text: str) -> str:
    """The text without its code blocks (kept as blank lines) and code spans."""
    blanked = FENCE.sub(lambda match: "\n" * match.group().count("\n"), text)
    return CODE_SPAN.sub("code", blanked)


def anchor(heading: str) -> str:
    """The anchor GitHub gives a heading: lower case, punctuation gone, spaces '-'."""
    text = re.sub(r"\[([^\]]*)\]\([^)]*\)", r"\1", heading).strip().lower()
    kept = "".join(
        char for char in text if char in " -_" or unicodedata.category(char)[0] in "LMN"
    )
    return kept.replace(" ", "-")


def anchors(text: str) -> set[str]:
    """Every heading's anchor; a repeated one gets -1, -2... as on GitHub."""
    seen: Counter[str] = Counter()
    found = set()
    for match in HEADING.finditer(FENCE.sub("", text)):
        slug = anchor(match.group(2))
        found.add(f"{slug}-{seen[slug]}" if seen[slug] else slug)
        seen[slug] += 1
    return found


def link_problems(files: Iterable[Path]) -> list[str]:
    """Relative links to a file that does not exist, or to an anchor it lacks."""
    problems = []
    for path in files:
        for target in LINK.findall(prose(path.read_text(encoding="utf-8"))):
            if target.startswith(EXTERNAL):
                continue
            file, _, fragment = target.partition("#")
            linked = (path.parent / file).resolve() if file else path
            if not linked.exists():
                problems.append(f"{path.name}: {target}: no such file")
            elif fragment and fragment not in anchors(
                linked.read_text(encoding="utf-8")
            ):
                problems.append(f"{path.name}: {target}: no such heading")
    return problems


def table_problems(path: Path) -> list[str]:
    """Tables whose rows a blank line cut off their header: shown as plain text."""
    problems = []
    lines = prose(path.read_text(encoding="utf-8")).split("\n")
    for number, line in enumerate(lines):
        starts = line.startswith("|") and (number == 0 or not lines[number - 1])
        if starts and not (
            number + 1 < len(lines) and re.match(r"\|[-:| ]+\|$", lines[number + 1])
        ):
            problems.append(f"{path.name}:{number + 1}: a table row without a header")
    return problems


def sections(text: str) -> Iterator[tuple[str, str]]:
    """Each second-level section of a page: its title and its body."""
    parts = re.split(r"^## (.+)$", prose(text), flags=re.MULTILINE)
    yield from zip(parts[1::2], parts[2::2], strict=True)


def test_every_link_and_anchor_resolves() -> None:
    assert link_problems(pages()) == []


def test_no_table_is_cut_by_a_blank_line() -> None:
    assert [problem for path in pages() for problem in table_problems(path)] == []


def test_the_readme_and_each_docs_page_stay_short() -> None:
    long = {
        str(path.relative_to(REPO)): lines
        for path in [README, *(REPO / "docs").glob("*.md")]
        if (lines := path.read_text(encoding="utf-8").count("\n")) > MAX_LINES
    }
    assert long == {}


def test_the_readme_starts_with_the_demo_and_what_it_needs() -> None:
    text = README.read_text(encoding="utf-8")
    title, body = next(sections(text))
    assert title == "Try it: the demo"
    assert "```sh\nscripts/develop\n```" in text.split("\n## ", 2)[1]
    for need in ("root on Debian or Ubuntu", "Debian testing", "5 minutes"):
        assert need in body
    assert "<http://localhost:8123>" in body


def test_the_readme_holds_both_set_up_commands_the_demo_and_the_tests() -> None:
    """A newcomer finds the demo's command and the tests' side by side, with their needs.

    The tests' command is the one CI runs (.ci/run calls it).
    """
    first = README.read_text(encoding="utf-8").split("\n## ", 2)[1]
    assert first.startswith("Try it: the demo")
    for command in ("scripts/develop", "scripts/test"):
        assert f"```sh\n{command}\n```" in first, command
        assert (REPO / command).is_file(), command
    tests = first.split("```sh\nscripts/test\n```", 1)[1]
    for said in ("What it needs:", "How long:", "minutes"):
        assert said in tests, said
    ci = (REPO / ".ci" / "run").read_text(encoding="utf-8")
    assert re.search(r"^exec bash scripts/test\b", ci, re.MULTILINE)
    assert "`.ci/run`" in first


def test_the_readme_says_the_licence() -> None:
    """Its section names the licence pyproject.toml declares and links the file."""
    licence = dict(sections(README.read_text(encoding="utf-8")))["Licence"]
    declared = tomllib.loads((REPO / "pyproject.toml").read_text(encoding="utf-8"))
    assert licence.lstrip().startswith(declared["project"]["license"])
    assert "](LICENSE)" in licence
    assert (REPO / "LICENSE").is_file()


def test_each_system_has_a_section_that_links_its_page() -> None:
    found = dict(sections(README.read_text(encoding="utf-8")))
    for title, page in SYSTEMS.items():
        assert f"]({page})" in found[title], title
        assert found[title].count("\n") <= 40, title


def test_the_mervis_section_says_where_an_example_vlist_is() -> None:
    mervis = dict(sections(README.read_text(encoding="utf-8")))["Mervis (Unipi)"]
    examples = re.findall(r"\]\(([^)]+\.vlist)\)", mervis)
    assert examples
    assert all((REPO / example).is_file() for example in examples)


def test_the_readme_lists_the_first_menu_as_it_reads() -> None:
    menu = json.loads(EN_JSON.read_text(encoding="utf-8"))["config"]["step"]["user"]
    text = README.read_text(encoding="utf-8")
    missing = [
        label for label in menu["menu_options"].values() if f"*{label}*" not in text
    ]
    assert missing == []


def test_a_message_that_sends_the_user_to_the_readme_finds_its_section() -> None:
    text = README.read_text(encoding="utf-8")
    titles = [title for title, _ in sections(text)]
    named = re.findall(r"README's (\w+) section", EN_JSON.read_text(encoding="utf-8"))
    assert [name for name in named if not any(t.startswith(name) for t in titles)] == []


def test_no_page_speaks_of_the_integration_as_tecomat_tecoapi() -> None:
    stale = [
        str(path.relative_to(REPO))
        for path in [README, *(REPO / "docs").glob("*.md")]
        if "Tecomat TecoApi" in path.read_text(encoding="utf-8")
    ]
    assert stale == []


def integration_name_problems(name: str, texts: Iterable[tuple[str, str]]) -> list[str]:
    """Where a text leads to the integration by another name than Home Assistant's.

    After *Devices & services →* (or *Add integration →*) comes the name the
    integration is listed under, or another part of that page (*Add
    integration*, *Discovered*).
    """
    problems = []
    for where, text in texts:
        for match in TO_THE_INTEGRATION.finditer(" ".join(text.split())):
            after = match.string[match.end() :]
            if not after.startswith((name, *OTHER_PARTS)):
                problems.append(f"{where}: → {after[:40]}")
    return problems


def translated_texts() -> Iterator[tuple[str, str]]:
    """Every text of both translations, with its key."""

    def walk(where: str, tree: object) -> Iterator[tuple[str, str]]:
        if isinstance(tree, dict):
            for key, value in tree.items():
                yield from walk(f"{where}.{key}", value)
        elif isinstance(tree, str):
            yield where, tree

    for language in ("en", "cs"):
        path = TRANSLATIONS / f"{language}.json"
        yield from walk(language, json.loads(path.read_text(encoding="utf-8")))


def test_the_pages_and_texts_name_the_integration_as_home_assistant_lists_it() -> None:
    """Not "PLC Bridge": Devices & services lists the manifest's name (issue 39)."""
    name = json.loads(MANIFEST.read_text(encoding="utf-8"))["name"]
    pages_texts = [
        (str(path.relative_to(REPO)), path.read_text(encoding="utf-8"))
        for path in pages()
    ]
    assert integration_name_problems(name, [*pages_texts, *translated_texts()]) == []


def test_the_readme_lists_the_demo_s_views_as_its_tabs() -> None:
    """In the order the dashboard's tabs show them (issue 39)."""
    views = yaml.safe_load(DEMO_DASHBOARD.read_text(encoding="utf-8"))["views"]
    for page in (README, REPO / "docs" / "development.md"):
        text = " ".join(page.read_text(encoding="utf-8").split())
        _, found, listed = text.partition("a view per system")
        listed = listed.split(". ", 1)[0]
        titles = [view["title"] for view in views]
        assert found, page.name
        assert all(title in listed for title in titles), (page.name, listed)
        assert sorted(titles, key=listed.index) == titles, (page.name, listed)


def test_checker_integration_name_problems_finds_another_name() -> None:
    texts = [
        ("a", "Open *Settings → Devices & services → PLC Bridge → the entry*."),
        ("b", "*Add integration* → *Long Name (X)* (search *X*)"),
        ("c", "Settings → Devices &\nservices → Add integration → Long Name (X)"),
    ]
    assert integration_name_problems("Long Name (X)", texts) == [
        "a: → PLC Bridge → the entry*."
    ]


def test_checker_anchor_is_githubs() -> None:
    assert anchor("3. Composition in the UI") == "3-composition-in-the-ui"
    assert anchor("PLCComS (`plccoms.py`)") == "plccoms-plccomspy"
    assert anchor("Tekon (ASUD.SCADA OPC-HTTP gateway)") == (
        "tekon-asudscada-opc-http-gateway"
    )
    assert anchor("Try it: the demo") == "try-it-the-demo"
    assert anchor("Přehled [a link](x.md)") == "přehled-a-link"
    assert anchors("# A\n## A\n```\n# B\n```\n") == {"a", "a-1"}


def test_checker_link_problems_finds_dead_links(tmp_path: Path) -> None:
    (tmp_path / "b.md").write_text("# Here\n", encoding="utf-8")
    page = tmp_path / "a.md"
    page.write_text(
        "# Top\n[ok](b.md#here) [ok](#top) [web](https://x.example/y)\n"
        "`[not a link](gone.md)`\n```\n[nor this](gone.md)\n```\n"
        "[file](gone.md) [heading](b.md#there) [own](#bottom)\n",
        encoding="utf-8",
    )
    assert link_problems([page]) == [
        "a.md: gone.md: no such file",
        "a.md: b.md#there: no such heading",
        "a.md: #bottom: no such heading",
    ]


def test_checker_table_problems_finds_a_row_cut_off(tmp_path: Path) -> None:
    page = tmp_path / "a.md"
    page.write_text(
        "| a | b |\n|---|---|\n| 1 | 2 |\n\n| 3 | 4 |\n\ntext\n", encoding="utf-8"
    )
    assert table_problems(page) == ["a.md:5: a table row without a header"]
