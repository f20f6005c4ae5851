"""Checks of the mesh helpers and the protocol's sharded passes, run by ``tests/test_mesh.py`` in a
subprocess with 4 host CPU devices (``XLA_FLAGS=--xla_force_host_platform_device_count=4``)."""

from __future__ import annotations

import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))  # run as a script from any folder

import jax  # noqa: E402
import jax.numpy as jnp  # noqa: E402
import numpy as np  # noqa: E402

from jaxmotion.data.pipeline import map_in_chunks  # noqa: E402
from jaxmotion.evaluation.protocol import generate  # noqa: E402
from jaxmotion.geometry.skeletons import SMPL24  # noqa: E402
from jaxmotion.models.recognition import Recognizer, RecognizerConfig, init_recognizer  # noqa: E402
from jaxmotion.distributed import data_mesh, replicate, shard_batch  # noqa: E402


def check_helpers():
    assert jax.device_count() == 4, jax.devices()
    mesh = data_mesh()
    assert mesh.shape == {"data": 4} and data_mesh(2).shape == {"data": 2}
    batch = shard_batch({"x": np.arange(16.0).reshape(8, 2), "y": np.arange(8)}, mesh)
    assert [s.data.shape for s in batch["x"].addressable_shards] == [(2, 2)] * 4
    np.testing.assert_array_equal(np.asarray(batch["y"]), np.arange(8))
    params = replicate({"w": jnp.ones(3), "key": jax.random.key(1)}, mesh)
    assert params["w"].sharding.is_fully_replicated and len(params["w"].addressable_shards) == 4
    for bad, message in [(lambda: shard_batch({"x": np.zeros((6, 2))}, mesh),
                          "batch size 6 is not divisible by the 4 devices"),
                         (lambda: data_mesh(5), "asked for 5 devices; 4 are available")]:
        try:
            bad()
        except ValueError as error:
            assert message in str(error), error
        else:
            raise AssertionError(f"no error: {message}")


def check_protocol_passes():
    mesh = data_mesh()
    rows = {"a": np.arange(10.0)[:, None] * np.ones((10, 3))}

    def square(i, part):
        return {"b": part["a"] ** 2 + i}

    # 10 rows in chunks of 3 -> chunks of 4 on 4 devices: same values, row for row
    plain, meshed = map_in_chunks(square, rows, 3), map_in_chunks(square, rows, 3, mesh=mesh)
    assert plain["b"].shape == meshed["b"].shape == (10, 3)
    np.testing.assert_array_equal(map_in_chunks(lambda i, p: {"b": p["a"] ** 2}, rows, 4)["b"],
                                  map_in_chunks(lambda i, p: {"b": p["a"] ** 2}, rows, 4, mesh=mesh)["b"])

    config = RecognizerConfig(hidden=16, layers=1, feature_dim=8)
    variables = init_recognizer(jax.random.key(0), config, SMPL24, 12, frames=30)
    one = Recognizer(config, SMPL24, tuple(str(i) for i in range(12)), variables, chunk=8)
    four = Recognizer(config, SMPL24, one.class_names, variables, chunk=8, mesh=mesh)

    def sampler(key, actions, durations):
        joints = jax.random.normal(key, (actions.shape[0], 30, 24, 3)) * 0.1 + actions[:, None, None, None] * 0.01
        return {"joints": joints, "lengths": durations}

    actions = np.arange(20) % 12
    a = generate(sampler, jax.random.key(2), actions, 30, 8)
    b = generate(sampler, jax.random.key(2), actions, 30, 8, mesh=mesh)
    np.testing.assert_array_equal(a["joints"], b["joints"])  # threefry bits do not depend on the sharding
    for x, y in zip(one(a), four(a), strict=True):
        np.testing.assert_allclose(x, y, rtol=1e-5, atol=1e-6)


if __name__ == "__main__":
    check_helpers()
    check_protocol_passes()
    print("mesh checks passed")
