# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""The house style of every figure tactex writes: one panel size, one dpi, legends outside.

A figure is a grid of panels, each `PANEL_IN` inches (a confusion matrix's panel grows
with its classes, `panel_in`), written at `DPI` at exactly that size: `save` lays the
figure out tight, making room for the legends `legend_outside` puts right of their axes,
so a legend never hides data and a PNG's size in pixels tells its grid of panels.
Plots follow the probe along its path where the data knows the position on it.
matplotlib is imported when a figure is made, with the file-only Agg backend.
"""

from __future__ import annotations

import math
from pathlib import Path
import warnings

PANEL_IN = (5.5, 4.0)  # width, height of one panel (inches), legend outside included
DPI = 110
# A confusion matrix's panel: square cells of CELL_IN plus CONFUSION_MARGIN_IN for the
# tick labels and the title; never smaller than PANEL_IN, wider by the same margin.
CELL_IN = 0.35
CONFUSION_MARGIN_IN = 2.0
LEGEND_FONTSIZE = 7
LEGEND_ROWS = 18  # entries in one legend column before the next column starts
FOOTNOTE_IN = 0.25  # the strip under the panels a footnote takes
# Rounds of adjustText's repulsion that move point labels apart: a fixed count (not its
# default one-second budget), so a figure comes out the same on a fast or a busy machine.
LABEL_ITERATIONS = 300


def panel_in(classes: int | None = None) -> tuple[float, float]:
    """One panel's (width, height) in inches; with `classes`, a confusion matrix's.

    The rule for a confusion matrix of `classes` rows or columns (the larger): its side is
    `CONFUSION_MARGIN_IN + CELL_IN * classes`, at least the panel's height, and it is as
    much wider than high as the panel is.
    """
    width, height = PANEL_IN
    if classes is None:
        return width, height
    side = max(height, CONFUSION_MARGIN_IN + CELL_IN * classes)
    return side + width - height, side


def figure(rows: int = 1, columns: int = 1, *, classes: int | None = None,
           **subplots_kwargs):
    """(pyplot, figure, axes) of `rows` x `columns` house-sized panels.

    Args:
        rows: panels down.
        columns: panels across.
        classes: for confusion matrices, the classes each panel shows (`panel_in`).
        **subplots_kwargs: passed on to `pyplot.subplots` (sharex, squeeze, ...).
    """
    import matplotlib
    matplotlib.use('Agg')
    import matplotlib.pyplot as plt
    width, height = panel_in(classes)
    made, axes = plt.subplots(rows, columns, figsize=(width * columns, height * rows),
                              **subplots_kwargs)
    return plt, made, axes


def legend_outside(axes, source=None) -> None:
    """`source`'s legend (default the axes' own) right of `axes`, where it hides no data."""
    handles, labels = (source or axes).get_legend_handles_labels()
    if handles:
        axes.legend(handles, labels, loc='upper left', bbox_to_anchor=(1.02, 1.0),
                    borderaxespad=0.0, fontsize=LEGEND_FONTSIZE,
                    ncol=math.ceil(len(handles) / LEGEND_ROWS))


def label_points(axes, xs, ys, labels, fontsize: float = 6) -> None:
    """Name each point (xs[i], ys[i]) of `axes` with labels[i], moved apart to be legible.

    adjustText pushes the labels off each other and off the points, and draws a thin line
    from a label that moved to its point. Call it once the axes' scales and limits are final.
    A point matplotlib does not draw (NaN or infinite) gets no label.
    """
    from adjustText import adjust_text
    drawn = [(x, y, label) for x, y, label in zip(xs, ys, labels, strict=True)
             if math.isfinite(x) and math.isfinite(y)]
    texts = [axes.text(x, y, label, fontsize=fontsize) for x, y, label in drawn]
    adjust_text(texts, x=[x for x, _, _ in drawn], y=[y for _, y, _ in drawn], ax=axes,
                iter_lim=LABEL_ITERATIONS,
                force_text=(0.3, 0.6), force_static=(0.2, 0.4), expand=(1.1, 1.5),
                time_lim=None, arrowprops={'arrowstyle': '-', 'color': '0.5', 'lw': 0.5})


def plain_log_ticks(axis) -> None:
    """Ticks of a log-scaled `axis` (`axes.xaxis`) at 1, 2 and 5 per decade, as plain numbers.

    A range under a decade then gets readable labels instead of matplotlib's crowded minor
    labels in scientific notation.
    """
    from matplotlib import ticker
    axis.set_major_locator(ticker.LogLocator(subs=(1.0, 2.0, 5.0)))
    axis.set_major_formatter(ticker.FuncFormatter(lambda value, _: f'{value:g}'))
    axis.set_minor_formatter(ticker.NullFormatter())


def save(plt, figure, path: Path, footnote: str | None = None) -> None:
    """Lay `figure` out tight (its legends too), write it at `DPI` to `path`, close it.

    Args:
        plt: pyplot, as `figure()` returned it.
        figure: the figure to write.
        path: the PNG to write.
        footnote: a line under the panels (what data the figure shows), if any.
    """
    bottom = 0.0
    if footnote:
        figure.text(0.5, 0.005, footnote, ha='center', va='bottom', fontsize=LEGEND_FONTSIZE,
                    color='dimgray', wrap=True)
        bottom = FOOTNOTE_IN / figure.get_size_inches()[1]
    with warnings.catch_warnings():  # a class named in a script no installed font has
        warnings.filterwarnings('ignore', 'Glyph .* missing from', UserWarning)
        figure.tight_layout(rect=(0, bottom, 1, 1))
        figure.savefig(path, dpi=DPI)
    plt.close(figure)
