"""Where jaxmotion keeps what it builds once and reuses: generated datasets, trained evaluators."""

from __future__ import annotations

import os
from pathlib import Path


def cache_root(cache_dir: str | Path | None = None) -> Path:
    """``cache_dir`` if given, else ``$JAXMOTION_CACHE``, else ``~/.cache/jaxmotion``."""
    return Path(cache_dir or os.environ.get("JAXMOTION_CACHE") or Path.home() / ".cache" / "jaxmotion")
