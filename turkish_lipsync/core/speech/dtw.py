"""Dynamic time warping of two feature sequences in memory that grows with their length, not its square.

Multi-resolution, as FastDTW does: the path is solved at a quarter of the frame rate, then refined in
a band around it (FastDTW halves; a quarter costs two thirds as much for the same paths on the tuning
takes). No DTW library is used: the ones that install cleanly either hold the full cost matrix
(dtw-python) or bring numba and librosa into a Blender extension; the recurrence is 40 lines of numpy.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

DTW_RADIUS = 12  # frames of slack around the coarse path at each resolution
SHRINK = 4  # frames of one resolution averaged into one of the next coarser
DTW_FULL_CELLS = 250_000  # below this many cells the DTW is solved without a band


@dataclass(frozen=True, eq=False)
class Pauses:
    """Where one signal may pause while the other does not, and what holding the other through it costs.

    x_free: frames of x that may be held while y pauses (x's word boundaries and its own silences), each
    step along y then costing at most y_hold_cost[j] (no step penalty). x_silent: x's own pauses, held
    against any frame of y at x_hold_cost a step (a pause in x that y does not make).
    """

    x_free: np.ndarray
    x_silent: np.ndarray
    y_hold_cost: np.ndarray
    x_hold_cost: float

    def shrunk(self) -> Pauses:
        return Pauses(
            _shrink_with(self.x_free, np.logical_or),
            _shrink_with(self.x_silent, np.logical_and),
            _shrink_with(self.y_hold_cost, np.maximum),
            self.x_hold_cost,
        )


def dtw_path(
    x: np.ndarray,
    y: np.ndarray,
    radius: int = DTW_RADIUS,
    step_penalty: float = 0.0,
    pauses: Pauses | None = None,
) -> tuple[np.ndarray, np.ndarray]:
    """The cheapest monotone path from (0, 0) to (len(x)-1, len(y)-1) through the frame distances.

    step_penalty: added to every horizontal or vertical step, so the path keeps near the diagonal where
    the distances alone do not decide (two voices never match as closely as one voice with itself).
    pauses: where a pause of one signal may be held against the other at a fixed cost (see Pauses).
    """
    n, m = len(x), len(y)
    if n * m <= DTW_FULL_CELLS or min(n, m) <= 4 * radius:
        return _band_dtw(x, y, np.zeros(n, np.int64), np.full(n, m, np.int64), step_penalty, pauses)
    coarse_i, coarse_j = dtw_path(
        _shrink(x), _shrink(y), radius, step_penalty, pauses.shrunk() if pauses is not None else None
    )
    low = np.full(n, m, np.int64)
    high = np.zeros(n, np.int64)
    for row_offset in range(SHRINK):
        rows = np.minimum(SHRINK * coarse_i + row_offset, n - 1)
        np.minimum.at(low, rows, SHRINK * coarse_j)
        np.maximum.at(high, rows, np.minimum(SHRINK * coarse_j + SHRINK, m))
    low = np.minimum.accumulate(low[::-1])[::-1]  # rows the projection missed borrow from their neighbours
    high = np.maximum.accumulate(high)
    grown_low, grown_high = low.copy(), high.copy()
    for shift in range(1, radius + 1):
        grown_low[shift:] = np.minimum(grown_low[shift:], low[:-shift])
        grown_high[:-shift] = np.maximum(grown_high[:-shift], high[shift:])
    grown_low = np.clip(grown_low - radius, 0, m)
    grown_high = np.clip(grown_high + radius, 0, m)
    grown_low[0], grown_high[-1] = 0, m
    return _band_dtw(x, y, grown_low, grown_high, step_penalty, pauses)


def coarse_dtw_path(
    x: np.ndarray, y: np.ndarray, step_penalty: float = 0.0, pauses: Pauses | None = None
) -> tuple[np.ndarray, np.ndarray]:
    """dtw_path solved at a quarter of the frame rate only, its steps spread back over the frames: where
    the path need only say which part of one signal meets which part of the other, at a third of the
    cost."""
    if len(x) * len(y) <= DTW_FULL_CELLS or min(len(x), len(y)) <= 4 * DTW_RADIUS * SHRINK:
        return dtw_path(x, y, step_penalty=step_penalty, pauses=pauses)
    coarse_i, coarse_j = dtw_path(
        _shrink(x), _shrink(y), step_penalty=step_penalty, pauses=pauses.shrunk() if pauses else None
    )
    offsets = np.arange(SHRINK)
    path_i = np.minimum((SHRINK * coarse_i)[:, None] + offsets, len(x) - 1).ravel()
    path_j = np.minimum((SHRINK * coarse_j)[:, None] + offsets, len(y) - 1).ravel()
    return path_i, path_j


def _shrink(features: np.ndarray) -> np.ndarray:
    """Means of SHRINK frames at a time (the last repeated to fill its group)."""
    groups = -(-len(features) // SHRINK)
    padded = np.concatenate((features, np.repeat(features[-1:], groups * SHRINK - len(features), axis=0)))
    return padded.reshape(groups, SHRINK, *features.shape[1:]).mean(axis=1)


def _shrink_with(values: np.ndarray, combine) -> np.ndarray:
    """values combined SHRINK frames at a time (np.logical_or, np.maximum, ...)."""
    groups = -(-len(values) // SHRINK)
    padded = np.concatenate((values, np.repeat(values[-1:], groups * SHRINK - len(values))))
    return combine.reduce(padded.reshape(groups, SHRINK), axis=1)


def _band_dtw(
    x: np.ndarray,
    y: np.ndarray,
    low: np.ndarray,
    high: np.ndarray,
    step_penalty: float = 0.0,
    pauses: Pauses | None = None,
) -> tuple[np.ndarray, np.ndarray]:
    """DTW (symmetric steps, diagonal weighted twice) with row i restricted to columns low[i]:high[i].

    low and high never decrease. Each row is solved at once: vertical and diagonal steps come from the
    row before (kept in one array over all columns, infinite outside its band), and the horizontal steps
    are a running minimum of (cost so far - cumulative distance), so no Python loop runs over cells. The
    distances are computed for blocks of rows at a time. Where pauses allow it, a free row's horizontal
    steps cost at most y's hold cost there, and a pause of x steps down any column for at most x's hold
    cost: only the step that holds one signal is made cheap.
    """
    if pauses is not None:
        x_hold_cost = float(pauses.x_hold_cost)
        y_hold_cost = pauses.y_hold_cost.astype(np.float64)
        x_free, x_silent = pauses.x_free.tolist(), pauses.x_silent.tolist()
    lows, highs = low.tolist(), high.tolist()
    width = max(1, max(h - lo for lo, h in zip(lows, highs, strict=True)))
    moves = np.empty((len(x), width), np.int8)  # per row: 0 diagonal, 1 from above, 2 from the left
    last = np.full(len(y) + 1, np.inf)  # last[1 + j]: the previous row's cost at column j
    previous_low = 0
    for block_begin, distances in _band_distances(x, y, low, high):
        straight = distances + step_penalty  # a horizontal or vertical step into each cell
        diagonal = 2 * distances
        for offset in range(len(distances)):
            i = block_begin + offset
            begin, end = lows[i], highs[i]
            size = end - begin
            across = down = straight[offset, :size]
            if pauses is not None and x_silent[i]:
                down = np.minimum(down, x_hold_cost)
            if pauses is not None and x_free[i]:
                across = np.minimum(across, y_hold_cost[begin:end])
            steps = np.add.accumulate(across)
            move = moves[i, :size]
            if i == 0:
                cost = steps
                move[:] = 2
            else:
                from_above = last[1 + begin : 1 + end] + down
                from_diagonal = last[begin:end] + diagonal[offset, :size]
                np.less(from_above, from_diagonal, out=move.view(bool))
                relative = np.minimum(from_diagonal, from_above, out=from_diagonal)
                relative -= steps
                best = np.minimum.accumulate(relative)
                move[best < relative] = 2
                cost = best + steps
            last[1 + previous_low : 1 + begin] = np.inf  # columns this row's band left behind
            last[1 + begin : 1 + end] = cost
            previous_low = begin
    return _backtrack(moves, lows, len(x) - 1, len(y) - 1)


def _backtrack(moves: np.ndarray, lows: list[int], i: int, j: int) -> tuple[np.ndarray, np.ndarray]:
    """The path from (i, j) back to (0, 0) through the recorded moves, in forward order."""
    # Plain bytes and ints: a step costs a few bytecodes instead of a numpy scalar lookup.
    width = moves.shape[1]
    flat = moves.tobytes()
    starts = [row * width - low for row, low in enumerate(lows)]
    path_i, path_j = [i], [j]
    while i or j:
        move = flat[starts[i] + j]
        if move == 0:
            i -= 1
            j -= 1
        elif move == 1:
            i -= 1
        else:
            j -= 1
        path_i.append(i)
        path_j.append(j)
    return np.array(path_i[::-1]), np.array(path_j[::-1])


def _band_distances(x: np.ndarray, y: np.ndarray, low: np.ndarray, high: np.ndarray):
    """(first row, distances of its rows to the columns of their bands, left-aligned) block by block."""
    width = int((high - low).max())
    rows_per_block = max(1, (1 << 17) // max(1, width * x.shape[1]))  # about a megabyte a block
    columns = np.arange(width)
    for begin in range(0, len(x), rows_per_block):
        rows = slice(begin, begin + rows_per_block)
        index = np.minimum(low[rows, None] + columns[None, :], len(y) - 1)
        difference = y[index] - x[rows, None, :]
        yield begin, np.sqrt(np.einsum("ijk,ijk->ij", difference, difference, dtype=np.float64))
