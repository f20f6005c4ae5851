"""Work around a known XLA CPU miscompilation, before the first jax computation.

jaxlib 0.10.x on CPU fuses ``(const * x[..., None, :]).sum(-1) * c`` through its experimental YNNPACK
path and returns wrong values (errors of several units on unit-scale inputs; reproduced in
``tests/test_xla_workarounds.py``). Turning that fusion off restores exact results at no measurable cost
here. XLA reads ``XLA_FLAGS`` when its backend starts, which is at the first computation, so setting it
when ``jaxmotion`` is imported works unless jax already ran something; the test catches a miss.
Other jaxlib versions are left alone: XLA rejects flags it does not know.
"""

from __future__ import annotations

import os
from importlib import metadata

YNN_FLAG = "--xla_cpu_experimental_ynn_fusion_type="
AFFECTED_JAXLIB = ("0.10.",)


def disable_ynn_fusion_if_affected() -> bool:
    """Add ``YNN_FLAG`` to ``XLA_FLAGS`` on affected jaxlib versions; True if the flag is now set."""
    try:
        version = metadata.version("jaxlib")
    except metadata.PackageNotFoundError:
        return False
    flags = os.environ.get("XLA_FLAGS", "")
    if "xla_cpu_experimental_ynn_fusion_type" in flags:
        return True
    if not version.startswith(AFFECTED_JAXLIB):
        return False
    os.environ["XLA_FLAGS"] = f"{flags} {YNN_FLAG}".strip()
    return True
