#!/usr/bin/env python3
"""The repository's own documents hold together:

- README.md, CONTRIBUTING.md and docs/*.md link only to files of the repository that exist (and
  to headings that exist in them), never outside it;
- no text names a document the repository does not have (DESIGN.md);
- LICENSE is the MIT licence; CITATION.cff names the paper and this version
  (`chainmail --version`);
- docs/command-line.md has a section for every subcommand `chainmail --help` lists.
"""
import argparse
import pathlib
import re
import subprocess
import sys

ROOT = pathlib.Path(__file__).resolve().parent.parent.parent
LINK = re.compile(r"\[[^\]]*\]\(([^)\s]+)\)")
HEADING = re.compile(r"^#+\s+(.*)$", re.MULTILINE)


def slug(heading):
    """A heading's anchor as the usual Markdown renderers make it."""
    text = heading.strip().lower().replace("`", "")
    text = re.sub(r"[^\w\- ]", "", text)
    return text.replace(" ", "-")


def check_links(errors):
    pages = [ROOT / "README.md", ROOT / "CONTRIBUTING.md", *sorted((ROOT / "docs").glob("*.md"))]
    for page in pages:
        for target in LINK.findall(page.read_text()):
            where = f"{page.relative_to(ROOT)}: link {target}"
            if re.match(r"[a-z]+:", target):
                errors.append(f"{where}: points outside the repository")
                continue
            path, _, anchor = target.partition("#")
            file = (page.parent / path).resolve() if path else page
            if not file.exists() or ROOT not in file.parents:
                errors.append(f"{where}: no such file in the repository")
            elif anchor and file.suffix == ".md":
                anchors = {slug(h) for h in HEADING.findall(file.read_text())}
                if anchor not in anchors:
                    errors.append(f"{where}: no heading #{anchor} in {file.relative_to(ROOT)}")
    return len(pages)


def check_missing_documents(errors):
    tracked = subprocess.run(["git", "ls-files"], cwd=ROOT, capture_output=True, text=True)
    files = tracked.stdout.split() if tracked.returncode == 0 else []
    if not files:  # not a git checkout (an exported tree): every text file
        files = [str(p.relative_to(ROOT)) for p in ROOT.rglob("*") if p.is_file()]
    for name in files:
        if name.startswith(("build/", "results/")) or name == "tests/cli/repo_docs.py":
            continue
        path = ROOT / name
        if path.suffix in (".md", ".hpp", ".cpp", ".txt", ".py", ".sh", ".json", ".cff"):
            if "DESIGN.md" in path.read_text(errors="replace"):
                errors.append(f"{name}: names DESIGN.md, which the repository does not have")


def check_licence_and_citation(chainmail, errors):
    if not (ROOT / "LICENSE").read_text().startswith("MIT License"):
        errors.append("LICENSE: not the MIT licence")
    citation = (ROOT / "CITATION.cff").read_text()
    version = subprocess.run([chainmail, "--version"], capture_output=True, text=True,
                             check=True).stdout.split()[0]
    if f"\nversion: {version}\n" not in citation:
        errors.append(f"CITATION.cff: not version {version} (chainmail --version)")
    for needed in ('title: "Plausible Chainmail Rendering"', "family-names: Mackenzie",
                   "family-names: Smith", "cff-version: 1.2.0"):
        if needed not in citation:
            errors.append(f"CITATION.cff: no {needed}")


def check_subcommands(chainmail, errors):
    help_text = subprocess.run([chainmail, "--help"], capture_output=True, text=True).stdout
    listed = re.findall(r"^  ([a-z]+)\s{2,}", help_text.split("Subcommands:")[1], re.MULTILINE)
    documented = (ROOT / "docs" / "command-line.md").read_text()
    for name in listed:
        if f"## `chainmail {name}" not in documented:
            errors.append(f"docs/command-line.md: no section for `chainmail {name}`")
    if len(listed) < 6:
        errors.append(f"chainmail --help lists only {listed}")


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--chainmail", required=True)
    args = parser.parse_args()
    errors = []
    pages = check_links(errors)
    check_missing_documents(errors)
    check_licence_and_citation(args.chainmail, errors)
    check_subcommands(args.chainmail, errors)
    for error in errors:
        print(f"FAIL {error}")
    print(f"repo_docs: {pages} pages, {len(errors)} failures")
    return 1 if errors else 0


if __name__ == "__main__":
    sys.exit(main())
