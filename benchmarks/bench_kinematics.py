"""Benchmark: forward kinematics of SMPL-24 poses, jit-compiled jaxmotion against a numpy loop.

    python benchmarks/bench_kinematics.py [--torch-ms-1200 4.4] [--budget-s 1.0]

The numpy baseline is the fair "loop over joints" implementation: vectorised over poses, one matrix
product per joint. Jax is timed after a warm-up call, with ``block_until_ready``; its first call (trace
and compile) is reported separately. Times are medians over repeats. Prints a markdown table.
"""

from __future__ import annotations

import argparse
import functools
import sys
import time
from pathlib import Path

import jax
import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))  # runnable from a checkout without installing

from benchmarks.timing import machine_header, median_ms  # noqa: E402
from jaxmotion.geometry.kinematics import forward_kinematics  # noqa: E402
from jaxmotion.geometry.rotations import axis_angle_to_matrix  # noqa: E402
from jaxmotion.geometry.skeletons import SMPL24, topological_order  # noqa: E402

# Measured on this machine with PyTorch's loop-over-joints FK (1 200 SMPL-24 poses, CPU); PyTorch is not
# a dependency, so the number is a constant.
TORCH_MS_1200 = 4.4

# [leading shape] per benchmarked pose count: 1 pose, a 20 x 60-frame batch, and a large batch.
SHAPES = {1: (1,), 1_200: (20, 60), 100_000: (1_000, 100)}


def numpy_forward_kinematics(local_rotmats, root_translation, offsets, parents):
    """[N, J, 3, 3], [N, 3], [J, 3] -> [N, J, 3], looping over joints in topological order."""
    rotations = np.empty_like(local_rotmats)
    joints = np.empty(local_rotmats.shape[:-1], local_rotmats.dtype)
    rotations[:, 0], joints[:, 0] = local_rotmats[:, 0], root_translation
    for joint in topological_order(parents)[1:]:
        parent = parents[joint]
        rotations[:, joint] = rotations[:, parent] @ local_rotmats[:, joint]
        joints[:, joint] = joints[:, parent] + rotations[:, parent] @ offsets[joint]
    return joints


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--torch-ms-1200", type=float, default=TORCH_MS_1200,
                        help="PyTorch loop-over-joints FK time at 1 200 poses, in ms (default: %(default)s)")
    parser.add_argument("--budget-s", type=float, default=1.0, help="timing budget per measurement, in s")
    args = parser.parse_args()

    print(machine_header())
    print()

    parents, offsets = SMPL24.parents, SMPL24.offsets
    rows = []
    for num_poses, shape in SHAPES.items():
        key_rotation, key_translation = jax.random.split(jax.random.PRNGKey(num_poses))
        local_rotmats = axis_angle_to_matrix(jax.random.normal(key_rotation, (*shape, SMPL24.num_joints, 3)))
        root_translation = jax.random.normal(key_translation, (*shape, 3))

        # The kernel as jitted code runs it: an eager call's rotation check (on by default) costs about as much
        # again, and the peers check nothing.
        fk = functools.partial(forward_kinematics, check=False)
        tick = time.perf_counter()
        joints = fk(local_rotmats, root_translation, offsets, parents).block_until_ready()
        compile_s = time.perf_counter() - tick
        jax_ms = median_ms(
            lambda: fk(local_rotmats, root_translation, offsets, parents).block_until_ready(),
            args.budget_s,
        )

        flat_rotmats = np.asarray(local_rotmats).reshape(num_poses, SMPL24.num_joints, 3, 3)
        flat_translation = np.asarray(root_translation).reshape(num_poses, 3)
        expected = numpy_forward_kinematics(flat_rotmats, flat_translation, offsets, parents)
        np.testing.assert_allclose(np.asarray(joints).reshape(expected.shape), expected, atol=1e-4)
        numpy_ms = median_ms(
            lambda: numpy_forward_kinematics(flat_rotmats, flat_translation, offsets, parents), args.budget_s
        )

        torch = f"{args.torch_ms_1200 / jax_ms:.1f}x faster" if num_poses == 1_200 else "-"
        rows.append(
            f"| {num_poses:,} ({' x '.join(map(str, shape))}) | {numpy_ms:.3f} | {jax_ms:.3f} "
            f"| {numpy_ms / jax_ms:.1f}x | {torch} | {compile_s:.2f} |"
        )

    print(
        f"| poses (shape) | numpy loop ms | jaxmotion jit ms | speed-up vs numpy "
        f"| vs PyTorch loop ({args.torch_ms_1200} ms @ 1,200) | jax first call (compile) s |"
    )
    print("|---|---:|---:|---:|---:|---:|")
    print("\n".join(rows))


if __name__ == "__main__":
    main()
