"""A sphinx-gallery image scraper for solverplan's figures.

The render functions return matplotlib ``Figure`` objects that are not registered with pyplot (they have their own
Agg canvas, so that the library never opens a window), so the stock matplotlib scraper does not see them. This one
collects every such figure that a block of an example left in the example's globals and that no earlier block
showed, in the order the names were bound, and saves it as the gallery's image.
"""

from __future__ import annotations

from typing import Any

from matplotlib.figure import Figure

_SHOWN = "_solverplan_gallery_shown"  # set on a figure once it is in the gallery


def solverplan_figures(block: Any, block_vars: dict[str, Any], gallery_conf: dict[str, Any], **kwargs: Any) -> str:
    from sphinx_gallery.scrapers import figure_rst

    figures = []
    for value in block_vars["example_globals"].values():
        if (isinstance(value, Figure) and value.canvas.manager is None  # pyplot's figures: the matplotlib scraper's
                and not getattr(value, _SHOWN, False) and all(value is not f for f in figures)):
            figures.append(value)
    paths = []
    for fig, path in zip(figures, block_vars["image_path_iterator"]):
        fig.savefig(path, dpi=110, bbox_inches="tight")
        setattr(fig, _SHOWN, True)
        paths.append(path)
    return figure_rst(paths, gallery_conf["src_dir"])
