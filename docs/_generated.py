"""Pages generated when the documentation builds, from the package's own reports, and the
gallery's scraper of the PNG files the example scripts write."""

from __future__ import annotations

import re
import shutil
from pathlib import Path

ERRATA_HEAD = "## Where the thesis is wrong"


def _section(markdown: str, head: str) -> str:
    """The section of ``markdown`` that starts at the line ``head`` and ends before the next
    heading of the same level."""
    start = markdown.index(head + "\n")
    level = head.split(" ", 1)[0]
    rest = markdown[start + len(head):]
    end = re.search(rf"^{level} ", rest, flags=re.M)
    return head + (rest if end is None else rest[:end.start()])


def _promote(markdown: str) -> str:
    """Every heading one level up (## -> #), so that a section becomes a page."""
    return re.sub(r"^#(#+ )", r"\1", markdown, flags=re.M)


def write_generated_pages(out: Path) -> None:
    """Run the quick validation report into ``out/validation`` (report.md and its chart), and
    write ``out/errata.md``: its section "Where the thesis is wrong", each finding with its
    evidence, the supporting cases of this run and the values recomputed now."""
    from spectralshell.reports import validation

    report_dir = out / "validation"
    shutil.rmtree(report_dir, ignore_errors=True)
    report = validation.run(report_dir, quick=True)
    if not report.passed:
        raise RuntimeError(f"the validation report has failures: see {report_dir / 'report.md'}")
    text = (report_dir / "report.md").read_text()
    (out / "errata.md").write_text(_promote(_section(text, ERRATA_HEAD)))


def png_scraper(block, block_vars, gallery_conf) -> str:
    """Move the PNG files an example wrote into its directory into the gallery's images."""
    from sphinx_gallery.scrapers import figure_rst

    src = Path(block_vars["src_file"]).parent
    images = []
    for png, target in zip(sorted(src.glob("*.png")), block_vars["image_path_iterator"]):
        shutil.move(png, target)
        images.append(target)
    return figure_rst(images, gallery_conf["src_dir"])
