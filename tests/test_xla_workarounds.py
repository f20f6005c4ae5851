"""A jaxlib CPU fusion that once returned wrong values must not do so under jaxmotion."""

import subprocess
import sys

import jax
import jax.numpy as jnp
import numpy as np
import pytest

import jaxmotion  # noqa: F401  (importing it applies the workaround)


def test_broadcast_multiply_sum_scale_is_computed_exactly():
    rng = np.random.default_rng(0)
    e = rng.normal(size=(24, 3, 3)).astype(np.float32)
    x = rng.normal(size=(1000, 24, 3)).astype(np.float32)
    expected = np.einsum("jab,fjb->fja", e, x) * np.float32(0.5)
    got = jax.jit(lambda v: (jnp.asarray(e) * v[..., None, :]).sum(-1) * 0.5)(x)
    np.testing.assert_allclose(np.asarray(got), expected, atol=1e-4)


@pytest.mark.integration
def test_importing_jaxmotion_first_protects_a_fresh_process():
    code = (
        "import jaxmotion, jax, jax.numpy as jnp, numpy as np\n"
        "r = np.random.default_rng(0)\n"
        "e = r.normal(size=(24, 3, 3)).astype(np.float32); x = r.normal(size=(1000, 24, 3)).astype(np.float32)\n"
        "got = jax.jit(lambda v: (jnp.asarray(e) * v[..., None, :]).sum(-1) * 0.5)(x)\n"
        "print(float(np.abs(np.asarray(got) - np.einsum('jab,fjb->fja', e, x) * 0.5).max()))\n"
    )
    env = {k: v for k, v in __import__("os").environ.items() if k != "XLA_FLAGS"}
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True, env=env)
    assert float(out.stdout.strip()) < 1e-4
