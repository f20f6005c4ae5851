"""Test-wide settings: float32 everywhere (the library default), a fixed hypothesis profile, one cache for the
session (smoke data, evaluators, compiled programs) and the markers' meaning.

Markers (``pyproject.toml``): ``smoke`` runs an experiment's smoke profile or trains for more than a few seconds;
``integration`` starts subprocesses (several processes, a killed and resumed run); ``browser`` drives the composer's
page in headless Chromium (also ``integration``). ``python -m pytest -m "not smoke and not integration"`` is the
unit tier; ``-m browser`` the browser tests alone.
"""

import os
from importlib import metadata

from hypothesis import HealthCheck, settings

# XLA:CPU's fusion emitters (the default since jaxlib 0.5) take twice as long to compile as the elemental emitters
# they replace (an ActFormer training step: 14 s against 6.5 s without optimisation passes), and the suite is
# compile-bound. Tests, and the subprocesses they start, use the older emitters; experiments keep XLA's default.
# Only on the jaxlib versions this was measured on: XLA aborts on a flag it does not know.
if metadata.version("jaxlib").startswith("0.10.") and "xla_cpu_use_fusion_emitters" not in os.environ.get("XLA_FLAGS", ""):
    os.environ["XLA_FLAGS"] = f"{os.environ.get('XLA_FLAGS', '')} --xla_cpu_use_fusion_emitters=false".strip()

import jaxmotion  # noqa: E402, F401  (first, so its XLA workaround is in place before any test computes)

# Compilation dominates small property tests; a few dozen examples per property is plenty and keeps CI fast.
settings.register_profile(
    "jaxmotion",
    max_examples=int(os.environ.get("JAXMOTION_HYPOTHESIS_EXAMPLES", "25")),
    deadline=None,
    derandomize=True,
    suppress_health_check=[HealthCheck.too_slow],
)
settings.load_profile("jaxmotion")


import functools  # noqa: E402
import gc  # noqa: E402
import pathlib  # noqa: E402
import shutil  # noqa: E402
import tempfile  # noqa: E402

import jax  # noqa: E402
import pytest  # noqa: E402

# One folder for the test session, empty at its start, shared by pytest-xdist's workers and the subprocesses tests
# start (they inherit the environment of the process that made it, which alone removes it at the end):
# - a compilation cache: the experiment smokes build the same tiny models and evaluators again and again (each in
#   its own jitted closures, which jax's in-memory cache does not match up), so each distinct computation compiles
#   once. Per session, so no test ever runs on a stale executable. Only programs that took a while to compile are
#   written: an eager op compiles faster than its cache entry is written and read back, and the suite runs
#   thousands of them.
# - one jaxmotion cache (a user's ~/.cache is never read): every smoke dataset and every smoke evaluator is made
#   once, by the first test that needs it, and read by the others (their folder locks let one process make what
#   another waits for). Tests of the cache itself point JAXMOTION_CACHE (or cache_dir) at folders of their own.
_OWNER = "JAXMOTION_TEST_SESSION" not in os.environ
if _OWNER:
    os.environ["JAXMOTION_TEST_SESSION"] = tempfile.mkdtemp(prefix="jaxmotion-test-")
_SESSION = pathlib.Path(os.environ["JAXMOTION_TEST_SESSION"])
os.environ["JAXMOTION_CACHE"] = str(_SESSION / "cache")
# The suite compiles thousands of small programs and runs each for a few steps, so XLA's optimisation passes cost
# more time than they save (unit modules: 30% less wall time without them). What a test checks does not depend on
# them; experiments and benchmarks run with XLA's defaults. Subprocesses get the same settings as this process.
_COMPILATION = {"jax_compilation_cache_dir": str(_SESSION / "xla"), "jax_persistent_cache_min_compile_time_secs": 0.5,
                "jax_persistent_cache_min_entry_size_bytes": 0, "jax_disable_most_optimizations": True}
for _name, _value in _COMPILATION.items():
    jax.config.update(_name, _value)
    os.environ[_name.upper()] = str(_value)


def pytest_collection_modifyitems(items):
    """Modules holding smoke or integration tests first, each module whole and in its own order (so its fixtures
    are set up once). pytest-xdist's workers then start on the long runs and end on short unit tests, which they
    share out, instead of one waiting at the end for the other's last experiment smoke."""
    heavy = {item.path for item in items if item.get_closest_marker("smoke") or item.get_closest_marker("integration")}
    items.sort(key=lambda item: item.path not in heavy)  # a stable sort


def pytest_sessionfinish(session, exitstatus):
    if _OWNER:
        shutil.rmtree(_SESSION, ignore_errors=True)


@pytest.fixture(autouse=True, scope="module")
def _release_executables():
    """Drop every compiled executable after each test module.

    Each XLA:CPU executable holds a few memory mappings of its own until it is released; the whole suite in one
    process compiles enough of them to pass Linux's limit of 65,530 mappings per process, and then LLVM's next
    allocation fails inside compilation (CI: exit 139 in `backend_compile_and_load`, after 40 minutes). What a
    later module needs again comes back from the session's compilation cache.
    """
    yield
    jax.clear_caches()
    gc.collect()


@pytest.fixture(scope="session")
def shared_dir() -> pathlib.Path:
    """The project's shared/ folder (beside the checkout, or $JAXMOTION_SHARED); skip tests when absent."""
    root = pathlib.Path(os.environ.get("JAXMOTION_SHARED", pathlib.Path(__file__).resolve().parents[2] / "shared"))
    if not (root / "a2m").is_dir():
        pytest.skip(f"shared reference files not found at {root} (set JAXMOTION_SHARED to their folder)")
    return root


@functools.cache
def _jitted(fn, static=()):
    return jax.jit(fn, static_argnames=static)


@pytest.fixture(params=["eager", "jit"])
def compile(request):
    """Run a kernel as it is or under ``jax.jit``: ``compile(fn, static=("num_classes",))(*args)``."""
    return (lambda fn, static=(): fn) if request.param == "eager" else _jitted
