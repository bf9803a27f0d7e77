"""P′ of an environment renumbered from P′ of the same rings started elsewhere equals the one computed directly."""

from __future__ import annotations

from hypothesis import given, settings
from hypothesis import strategies as st

from solverplan.bounce.partitions import partition, renumbered
from solverplan.environment import Environment
from solverplan.plan._walls import PartitionedWalls as Walls

from tests.strategies import polygons_with_holes


@settings(max_examples=40)
@given(polygons_with_holes(), st.data())
def test_renumbered_partition_equals_the_partition_of_the_turned_rings(env, data):
    shifts = [data.draw(st.integers(0, len(ring) - 1)) for ring in env.rings]
    turned = Environment.from_coords([list(r[k:] + r[:k]) for r, k in zip(env.rings, shifts)][0],
                                     [list(r[k:] + r[:k]) for r, k in zip(env.rings, shifts)][1:])
    offsets = env.ring_offsets
    vertex_of = [offsets[ring] + (i - shifts[ring]) % len(env.rings[ring])
                 for ring in range(len(env.rings)) for i in range(len(env.rings[ring]))]
    assert renumbered(partition(env), turned, vertex_of) == partition(turned)


def test_the_walls_give_the_users_partition_without_a_second_cast():
    env = Environment.from_coords([[0, 0], [4, 0], [4, 1], [0, 2]], [[[1, 0.5], [1.5, 0.5], [1.5, 1]]])
    walls = Walls(env)
    assert not walls.identity and walls.merged.n_vertices == env.n_vertices
    assert walls.user_partition == partition(env)
