"""Virtual doors: the rooms as walls a robot bounces on, doors that let it through or turn it back, and the
door-control policy of the paper's §V–VI.

:class:`RoomWorld` is the decomposed polygon as the simulator sees it (:class:`solverplan.rollout.PolicyWalls`):
the walls are the sides of the rooms — every side of every room, numbered room after room, so a door is two
walls, one in each of its rooms — and a ray is cast in the room it starts in (the batch ray caster on the
room's own polygon). When it reaches a door that is **open** for its rollout it goes on, straight, into the
next room; a **closed** door is a wall: the robot bounces off it. Which doors are open is asked of a
function ``is_open(rollouts, doors)``, so it can change from bounce to bounce and from robot to robot.

:class:`DoorControl` is the paper's central system for a room sequence (a path from a start room to a target,
or a tour of every room): the robot in room ``walk[k]`` may only move on along the sequence. The doors open
at position k are those of the longest stretch ``walk[k], walk[k+1], …`` that visits no room twice; every
other door is closed. So doors to rooms off the sequence are closed from the start, the door behind the
robot closes as it enters the next room, and when the next room is a dead end the door it came through is
the way on and stays open until the robot is back (the paper's exact words for a path, extended to tours
that come back through a room).

>>> from solverplan.environment import load_environment
>>> from solverplan.rectilinear.decomposition import decompose_rooms
>>> dec = decompose_rooms(load_environment("three_chambers"))
>>> control = DoorControl(dec, dec.path(0, 2))
>>> control.walk, [sorted(control.open_doors(k)) for k in range(len(control.walk))]
((0, 4, 1, 3, 2), [[0, 1, 2, 3], [1, 2, 3], [2, 3], [3], []])
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from functools import cached_property
from typing import Any, Callable, Sequence

import numpy as np

from solverplan.environment import Environment
from solverplan.errors import InputError
from solverplan.geometry.raycast import RayHits, cast_from_boundary, cast_rays, heading_directions
from solverplan.rectilinear.decomposition import Decomposition

__all__ = ["RoomWorld", "DoorControl", "room_environment"]

IsOpen = Callable[[np.ndarray, np.ndarray], np.ndarray]
"""``is_open(rollouts, doors)``: for each pair, whether that rollout's robot may pass that door (bool array)."""


def room_environment(dec: Decomposition, room: int) -> Environment:
    """Room ``room`` as an environment of its own (:attr:`Decomposition.room_environments`)."""
    return dec.room_environments[dec.check_room(room)]


@dataclass(frozen=True, eq=False)
class RoomWorld:
    """The rooms of a decomposition as the walls of a simulation (module docstring).

    Parameters
    ----------
    dec
        The decomposition.
    is_open
        Which doors are open per rollout; ``None``: every door is open (the robot moves in P as if there were
        no doors, but its contacts say which room it is in).
    """

    dec: Decomposition
    is_open: IsOpen | None = None

    # ------------------------------------------------------------------ numbering
    @cached_property
    def rooms(self) -> tuple[Environment, ...]:
        return self.dec.room_environments

    @cached_property
    def offsets(self) -> np.ndarray:
        """The first wall id of each room, then the number of walls."""
        return np.concatenate([[0], np.cumsum([env.n_edges for env in self.rooms])]).astype(np.int64)

    @property
    def n_edges(self) -> int:
        return int(self.offsets[-1])

    @cached_property
    def room_of(self) -> np.ndarray:
        """The room of every wall (int array)."""
        return np.repeat(np.arange(len(self.rooms)), np.diff(self.offsets))

    @cached_property
    def door_of(self) -> np.ndarray:
        """The door each wall is (−1 for a wall that is not a door)."""
        return np.concatenate([np.asarray(room.sides, dtype=np.int64) for room in self.dec.rooms])

    @cached_property
    def twin(self) -> np.ndarray:
        """For a door wall, the same door as a wall of the room on its other side (−1 for walls)."""
        out = np.full(self.n_edges, -1, dtype=np.int64)
        sides: dict[int, list[int]] = {}
        for wall, door in enumerate(self.door_of.tolist()):
            if door >= 0:
                sides.setdefault(door, []).append(wall)
        for a, b in sides.values():
            out[a], out[b] = b, a
        return out

    @cached_property
    def edge_start(self) -> np.ndarray:
        return np.concatenate([env.edge_start for env in self.rooms])

    @cached_property
    def edge_end(self) -> np.ndarray:
        return np.concatenate([env.edge_end for env in self.rooms])

    @cached_property
    def edge_lengths(self) -> np.ndarray:
        return np.concatenate([env.edge_lengths for env in self.rooms])

    def walls_of(self, room: int) -> np.ndarray:
        """Wall ids of room ``room`` that are not doors."""
        ids = np.arange(self.offsets[room], self.offsets[room + 1])
        return ids[self.door_of[ids] < 0]

    # ------------------------------------------------------------------ the PolicyWalls protocol
    def points_at(self, edges: np.ndarray, t: np.ndarray) -> np.ndarray:
        edges = np.asarray(edges, dtype=np.int64)
        t = np.asarray(t, dtype=float)
        a, b = self.edge_start[edges], self.edge_end[edges]
        return a + t[..., None] * (b - a)

    def directions(self, edges: np.ndarray, headings: np.ndarray) -> np.ndarray:
        edges = np.asarray(edges, dtype=np.int64).reshape(-1)
        headings = np.asarray(headings, dtype=float).reshape(-1)
        out = np.empty((len(edges), 2))
        rooms = self.room_of[edges]
        for r in np.unique(rooms).tolist():
            rows = np.flatnonzero(rooms == r)
            out[rows] = heading_directions(self.rooms[r], edges[rows] - self.offsets[r], headings[rows])
        return out

    def headings_of(self, edges: np.ndarray, directions: np.ndarray) -> np.ndarray:
        """Headings (CCW from the walls ``edges``) of world directions pointing into their rooms."""
        d = self.edge_end[edges] - self.edge_start[edges]
        d = d / np.hypot(d[:, 0], d[:, 1])[:, None]
        cross = d[:, 0] * directions[:, 1] - d[:, 1] * directions[:, 0]
        dot = np.einsum("ij,ij->i", d, directions)
        return np.arctan2(cross, dot)

    def cast(self, contacts: Any, headings: np.ndarray, *, exact_ties: bool = False) -> RayHits:
        """Cast each contact's ray in its room; through open doors it goes on into the next room.

        ``contacts`` has ``edge``, ``t`` (walls of this world) and ``rollout`` (for ``is_open``). Returns the
        hits on this world's walls; ``s`` is the whole distance travelled, ``vertex`` a wall id when the ray
        ends at (within the caster's tolerance of) a room corner.
        """
        edges = np.asarray(contacts.edge, dtype=np.int64)
        t = np.asarray(contacts.t, dtype=float)
        rollout = np.asarray(contacts.rollout, dtype=np.int64)
        h = np.asarray(headings, dtype=float)
        m = len(edges)
        out_edge = np.full(m, -1, dtype=np.int64)
        out_t = np.full(m, np.nan)
        out_x, out_y = np.full(m, np.nan), np.full(m, np.nan)
        out_s = np.zeros(m)
        out_vertex = np.full(m, -1, dtype=np.int64)
        out_uncertain = np.zeros(m, dtype=bool)
        todo = np.arange(m)
        cur_e, cur_t, cur_h = edges.copy(), t.copy(), h.copy()
        for _ in range(len(self.dec.doors) + 1):  # a straight ray crosses each door at most once
            if len(todo) == 0:
                break
            rooms = self.room_of[cur_e[todo]]
            next_todo: list[np.ndarray] = []
            for r in np.unique(rooms).tolist():
                rows = todo[rooms == r]
                local = cur_e[rows] - self.offsets[r]
                hits = cast_from_boundary(self.rooms[r], local, cur_t[rows], cur_h[rows], exact_ties=exact_ties)
                wall = np.where(hits.edge >= 0, hits.edge + self.offsets[r], -1)
                out_s[rows] += np.nan_to_num(hits.s)
                flagged = hits.uncertain | (hits.vertex >= 0) | (wall < 0)
                door = np.where(wall >= 0, self.door_of[np.maximum(wall, 0)], -1)
                through = ~flagged & (door >= 0)
                if through.any() and self.is_open is not None:
                    through[through] = np.asarray(self.is_open(rollout[rows[through]], door[through]), dtype=bool)
                stop = ~through
                done = rows[stop]
                out_edge[done], out_t[done] = wall[stop], hits.t[stop]
                out_x[done], out_y[done] = hits.x[stop], hits.y[stop]
                out_vertex[done] = np.where(hits.vertex[stop] >= 0, wall[stop], -1)
                out_uncertain[done] = hits.uncertain[stop] | (wall[stop] < 0)
                if through.any():
                    go = rows[through]
                    v = heading_directions(self.rooms[r], local[through], cur_h[go])
                    twin = self.twin[wall[through]]
                    cur_e[go], cur_t[go] = twin, 1.0 - hits.t[through]
                    cur_h[go] = np.clip(self.headings_of(twin, v), 1e-12, math.pi - 1e-12)
                    next_todo.append(go)
            todo = np.concatenate(next_todo) if next_todo else np.zeros(0, dtype=np.int64)
        return RayHits(out_edge, out_t, out_x, out_y, out_s, out_vertex, out_uncertain)

    # ------------------------------------------------------------------ starts
    def starts_in(self, room: int, n: int, rng: np.random.Generator) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """``n`` robots at uniform random points of room ``room`` moving in uniform random directions, as the
        simulator starts them: the wall behind each (where its line of motion came from), the position
        there, and the heading. Returns ``(walls, t, headings)``."""
        import shapely

        self.dec.check_room(room)
        env = self.rooms[room]
        polygon = env.to_shapely()
        x0, y0, x1, y1 = polygon.bounds
        walls, ts, hs = [], [], []
        have = 0
        for _ in range(100):
            k = max(2 * (n - have), 16)
            p = np.column_stack([rng.uniform(x0, x1, k), rng.uniform(y0, y1, k)])
            p = p[shapely.contains_xy(polygon, p[:, 0], p[:, 1])]
            angle = rng.uniform(0.0, 2 * math.pi, len(p))
            d = np.column_stack([np.cos(angle), np.sin(angle)])
            back = cast_rays(env, p, -d)
            ok = ~back.uncertain & (back.edge >= 0)
            wall = back.edge[ok] + self.offsets[room]
            heading = self.headings_of(wall, d[ok])
            ok2 = (heading > 1e-9) & (heading < math.pi - 1e-9)
            walls.append(wall[ok2])
            ts.append(back.t[ok][ok2])
            hs.append(heading[ok2])
            have += int(ok2.sum())
            if have >= n:
                break
        if have < n:  # pragma: no cover - a room of positive area always has interior points
            raise InputError(f"could not place {n} robots in room {room}")
        return (np.concatenate(walls)[:n], np.concatenate(ts)[:n], np.concatenate(hs)[:n])


class DoorControl:
    """The door-control policy for a room sequence ``walk`` (module docstring).

    Parameters
    ----------
    dec
        The decomposition.
    walk
        Room ids, each a neighbour of the one before (a path from :meth:`Decomposition.path`, a tour from
        :meth:`Decomposition.tour`).
    """

    def __init__(self, dec: Decomposition, walk: Sequence[int]) -> None:
        walk = tuple(int(dec.check_room(r)) for r in walk)
        if not walk:
            raise InputError("a room sequence needs at least one room")
        for i, j in zip(walk, walk[1:]):
            dec.door_between(i, j)  # raises for rooms that are not neighbours
        self.dec = dec
        self.walk = walk
        self._end: list[int] = []  # the end of the longest stretch from k without a repeated room
        for k in range(len(walk)):
            seen = {walk[k]}
            end = k
            while end + 1 < len(walk) and walk[end + 1] not in seen:
                end += 1
                seen.add(walk[end])
            self._end.append(end)
        n_doors = len(dec.doors)
        self._open = np.zeros((len(walk), max(n_doors, 1)), dtype=bool)
        for k in range(len(walk)):
            for i in range(k, self._end[k]):
                self._open[k, dec.door_between(walk[i], walk[i + 1]).id] = True

    def open_doors(self, k: int) -> set[int]:
        """The doors open while the robot is at position ``k`` of the walk."""
        return set(np.flatnonzero(self._open[k]).tolist())

    def is_open(self, positions: np.ndarray, doors: np.ndarray) -> np.ndarray:
        """Vectorised: is door ``doors[i]`` open for a robot at walk position ``positions[i]``?"""
        return self._open[np.asarray(positions, dtype=np.int64), np.asarray(doors, dtype=np.int64)]

    def advance(self, positions: np.ndarray, rooms: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """New walk positions of robots at ``positions`` now in ``rooms``, and whether each move was allowed
        (the room is on the open stretch ahead; a robot that stays put keeps its position)."""
        positions = np.asarray(positions, dtype=np.int64)
        rooms = np.asarray(rooms, dtype=np.int64)
        new = positions.copy()
        ok = np.ones(len(positions), dtype=bool)
        for i, (k, room) in enumerate(zip(positions.tolist(), rooms.tolist())):
            if self.walk[k] == room:
                continue
            for j in range(k + 1, self._end[k] + 1):
                if self.walk[j] == room:
                    new[i] = j
                    break
            else:
                ok[i] = False
        return new, ok

    @property
    def last(self) -> int:
        return len(self.walk) - 1
