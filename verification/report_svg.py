"""Figures of the verification report as inline SVG: matplotlib without pyplot, no embedded fonts.

Shared by the report (`verification.report`) and its cross-code section (`verification.report_cross_code`).
"""

from __future__ import annotations

import io
import re


def inline_svg(fig):
    """Inline <svg> of a matplotlib Figure (labels kept as SVG text in a common sans-serif: no embedded fonts)."""
    import matplotlib
    buf = io.StringIO()
    with matplotlib.rc_context({"svg.fonttype": "none", "svg.hashsalt": "gfmd-report",
                                "font.family": ["DejaVu Sans", "Helvetica", "Arial", "sans-serif"]}):
        fig.savefig(buf, format="svg", bbox_inches="tight")
    text = buf.getvalue()
    start = text.find("<svg")  # drop the XML prolog and DOCTYPE: not allowed inside HTML
    text = text[start:] if start >= 0 else text
    # inline SVG in HTML5 needs no namespace declarations nor the RDF metadata block: dropping them
    # leaves the page with no http(s) URL at all (they are names, not fetched, but checks stay simple)
    text = re.sub(r"<metadata>.*?</metadata>\s*", "", text, flags=re.S)
    text = re.sub(r'\s+xmlns(:\w+)?="[^"]*"', "", text, count=3)
    return text


def figure_axes(nrows=1, figsize=(7.5, 3.8), **kw):
    """(Figure, axes) without pyplot: no global state, no GUI backend."""
    from matplotlib.figure import Figure
    fig = Figure(figsize=figsize)
    return fig, fig.subplots(nrows, 1, **kw)
