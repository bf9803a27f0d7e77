"""Where the shipped environment files live: ``solverplan/models/*.json``, installed as package data.

:mod:`solverplan.models` is their public face (``names``, ``path``, ``load``). The lookup itself lives here,
at the bottom of the layers, so that :func:`solverplan.environment.load_environment` can accept a shipped
model's name where a file is expected without importing a layer to its right.
"""

from __future__ import annotations

from pathlib import Path

MODELS_DIR = Path(__file__).resolve().parent / "models"


def model_names() -> list[str]:
    """The names of the shipped models (file stems), sorted."""
    return sorted(path.stem for path in MODELS_DIR.glob("*.json"))


def model_file(name: str) -> Path | None:
    """The file of the shipped model ``name`` (with or without ``.json``), or None if there is none.

    A name with a directory part is never a model's: ``data/square.json`` means that file, not the model.
    """
    if "/" in name or "\\" in name:
        return None
    stem = name.removesuffix(".json")
    return MODELS_DIR / f"{stem}.json" if stem in model_names() else None
