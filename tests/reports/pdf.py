"""Reading back the PDFs the reports write: their pages' paper sizes, and their text as
poppler's ``pdftotext`` reads it (the tests of the sheets, the templates and the route
studies share these)."""

from __future__ import annotations

import os
import re
import subprocess
from pathlib import Path

import pytest

PDFTOTEXT = "/usr/bin/pdftotext"
IN_CI = os.environ.get("CI", "").lower() in ("1", "true", "yes")


def pdf_pages(data: bytes) -> list[tuple[float, float]]:
    """The (width, height) in points of every page of a PDF (a minimal parse: matplotlib
    writes one ``/Type /Page`` object with its ``/MediaBox`` per page)."""
    pages = []
    for m in re.finditer(rb"<<[^>]*?/Type\s*/Page\b(?!s).*?>>", data, re.S):
        box = re.search(rb"/MediaBox\s*\[\s*0\s+0\s+([\d.]+)\s+([\d.]+)\s*\]", m.group(0))
        pages.append((float(box.group(1)), float(box.group(2))) if box else (0.0, 0.0))
    return pages


def pdf_text(path: Path, page: int | None = None) -> str:
    """The text of a PDF (one page, or all) as poppler's pdftotext reads it."""
    if not os.path.exists(PDFTOTEXT):
        if IN_CI:
            pytest.fail("pdftotext is missing in CI: .ci/run installs poppler-utils")
        pytest.skip("poppler's pdftotext is absent (apt-get install poppler-utils)")
    pages = [] if page is None else ["-f", str(page), "-l", str(page)]
    return subprocess.run([PDFTOTEXT, "-layout", *pages, str(path), "-"], check=True,
                          capture_output=True, text=True).stdout
