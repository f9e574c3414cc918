"""Front-view depth maps of a mesh: how far forward (-Y) its surface comes at each point of a grid."""

from __future__ import annotations

import numpy as np

from ..base.errors import HeadError

# Bounds on a depth map whatever the mesh: its pixels, the pixel samples of all its triangles' boxes
# (a real head's front view takes a few hundred thousand; 3,000 vertices in 4,000 random triangles asked
# for 400 million and 13 GB), and the samples rasterised at once.
MAX_PIXELS = 16_000_000
MAX_SIDE = 8192
MAX_SAMPLES = 40_000_000
# How many times over the triangles' boxes may cover the view: the shared heads cover theirs 2.2 to 4.6
# times (MakeHuman's whole body with its helpers 4.6), random triangles over a cloud of points hundreds of
# times, which would take a minute of rasterising for every view the landmark search tries.
MAX_COVER = 40.0
CHUNK_SAMPLES = 1_000_000


class DepthMap:
    """How far forward (-Y) the surface comes at each point of a front-view grid; NaN where no surface.

    Pixel (row, column) looks at x = left + column * pixel, z = top - row * pixel.
    """

    def __init__(self, vertices: np.ndarray, triangles: np.ndarray, pixel: float, like=None) -> None:
        """like: another DepthMap whose grid this one shares (to compare what two meshes show). A grid of
        more than MAX_PIXELS (or MAX_SIDE a side) takes coarser pixels: memory stays bounded whatever the
        mesh's extent."""
        self.pixel = pixel
        if like is not None:
            self.pixel, self.left, self.top = like.pixel, like.left, like.top
            rows, columns = like.front.shape
        else:
            used = vertices[np.unique(triangles)]
            extent = np.ptp(used[:, [0, 2]], axis=0) + 4 * pixel
            if np.prod(extent / pixel) > MAX_PIXELS or np.max(extent / pixel) > MAX_SIDE:
                pixel = max(float(np.sqrt(np.prod(extent) / MAX_PIXELS)), float(np.max(extent)) / MAX_SIDE)
                self.pixel = pixel
            self.left = used[:, 0].min() - 2 * pixel
            self.top = used[:, 2].max() + 2 * pixel
            columns = int(np.ceil((used[:, 0].max() + 2 * pixel - self.left) / pixel)) + 1
            rows = int(np.ceil((self.top - used[:, 2].min() + 2 * pixel) / pixel)) + 1
        self.front = self._rasterise(vertices, triangles, rows, columns)

    def _rasterise(self, vertices: np.ndarray, triangles: np.ndarray, rows: int, columns: int) -> np.ndarray:
        """The front surface, triangle by triangle over the pixels of its box, in chunks of about
        CHUNK_SAMPLES pixels; a mesh whose triangles' boxes hold more than MAX_SAMPLES pixels in all is
        refused (no head's surface covers its front view that many times over)."""
        u = (vertices[:, 0] - self.left) / self.pixel
        v = (self.top - vertices[:, 2]) / self.pixel
        forward = -vertices[:, 1]
        tu, tv = u[triangles], v[triangles]
        # Clipped to the grid: a map sharing another's grid may hold triangles beyond it.
        u0 = np.maximum(np.ceil(tu.min(1)), 0).astype(np.int64)
        u1 = np.minimum(np.floor(tu.max(1)), columns - 1).astype(np.int64)
        v0 = np.maximum(np.ceil(tv.min(1)), 0).astype(np.int64)
        v1 = np.minimum(np.floor(tv.max(1)), rows - 1).astype(np.int64)
        counts = np.clip(u1 - u0 + 1, 0, None) * np.clip(v1 - v0 + 1, 0, None)
        total = int(counts.sum())
        if total > MAX_SAMPLES or total > MAX_COVER * rows * columns:
            raise HeadError(
                f"The mesh's {len(triangles):,} triangles cover its front view "
                f"{total / max(rows * columns, 1):,.0f} times over: that is no head's surface (a head "
                "covers it a few times). Remove stray or overlapping faces (Mesh > Clean Up), or import "
                "the head mesh alone."
            )
        image = np.full(rows * columns, -np.inf)
        tf = forward[triangles]
        for chunk, first_rows, last_rows in _chunks(counts, u0, u1, v0, v1):
            self._rasterise_chunk(
                image, columns, tu[chunk], tv[chunk], tf[chunk], u0[chunk], first_rows, u1[chunk], last_rows
            )
        image = image.reshape(rows, columns)
        image[~np.isfinite(image)] = np.nan
        return image

    @staticmethod
    def _rasterise_chunk(image, columns, tu, tv, tf, u0, v0, u1, v1) -> None:
        """Rasterise triangles (their corners' grid coordinates tu, tv and depths tf) over the pixels of
        their boxes, columns u0..u1 and rows v0..v1, into the flat image (the front-most depth wins)."""
        span_u = np.clip(u1 - u0 + 1, 0, None)
        counts = span_u * np.clip(v1 - v0 + 1, 0, None)
        owner = np.repeat(np.arange(len(tu)), counts)
        local = np.arange(owner.size) - np.repeat(np.cumsum(counts) - counts, counts)
        pu = u0[owner] + local % np.maximum(span_u[owner], 1)
        pv = v0[owner] + local // np.maximum(span_u[owner], 1)
        a_u, b_u, c_u = tu[owner].T
        a_v, b_v, c_v = tv[owner].T
        area = (b_u - a_u) * (c_v - a_v) - (c_u - a_u) * (b_v - a_v)
        with np.errstate(divide="ignore", invalid="ignore"):
            w_b = ((pu - a_u) * (c_v - a_v) - (c_u - a_u) * (pv - a_v)) / area
            w_c = ((b_u - a_u) * (pv - a_v) - (pu - a_u) * (b_v - a_v)) / area
            w_a = 1.0 - w_b - w_c
            tolerance = -1e-9
            inside = (area != 0) & (w_a >= tolerance) & (w_b >= tolerance) & (w_c >= tolerance)
        f = tf[owner[inside]]
        depth = w_a[inside] * f[:, 0] + w_b[inside] * f[:, 1] + w_c[inside] * f[:, 2]
        np.maximum.at(image, pv[inside] * columns + pu[inside], depth)

    def column_of(self, x: float) -> int:
        return int(round((x - self.left) / self.pixel))

    def row_of(self, z: float) -> int:
        return int(round((self.top - z) / self.pixel))

    def x_of(self, column) -> np.ndarray:
        return self.left + np.asarray(column, np.float64) * self.pixel

    def z_of(self, row) -> np.ndarray:
        return self.top - np.asarray(row, np.float64) * self.pixel

    def point(self, row: int, column: int) -> np.ndarray:
        """The surface point seen at a pixel, in head coordinates."""
        return np.array([self.x_of(column), -self.front[row, column], self.z_of(row)])


def _chunks(counts: np.ndarray, u0: np.ndarray, u1: np.ndarray, v0: np.ndarray, v1: np.ndarray):
    """(triangles, their first rows, their last rows) of about CHUNK_SAMPLES pixels each, in order: a run
    of whole triangles' boxes, or one triangle bigger than a chunk a band of its box's rows at a time."""
    start, running = 0, np.cumsum(counts)
    while start < len(counts):
        before = running[start - 1] if start else 0
        stop = max(int(np.searchsorted(running, before + CHUNK_SAMPLES, "right")), start + 1)
        chunk = slice(start, stop)
        if stop == start + 1 and counts[start] > CHUNK_SAMPLES:
            step = max(1, CHUNK_SAMPLES // max(int(u1[start] - u0[start] + 1), 1))
            for first in range(int(v0[start]), int(v1[start]) + 1, step):
                yield chunk, np.array([first]), np.array([min(first + step - 1, int(v1[start]))])
        else:
            yield chunk, v0[chunk], v1[chunk]
        start = stop


def box_blur(image: np.ndarray, radius: int) -> np.ndarray:
    """Mean over a (2r+1)^2 window, edges clamped; summed-area table so it costs the same at any radius."""
    padded = np.pad(image, radius + 1, mode="edge")
    table = padded.cumsum(0).cumsum(1)
    size = 2 * radius + 1
    total = table[size:, size:] - table[:-size, size:] - table[size:, :-size] + table[:-size, :-size]
    return total[: image.shape[0], : image.shape[1]] / size**2


def hidden_depth(vertices: np.ndarray, depth: DepthMap) -> np.ndarray:
    """How far each vertex lies behind the surface the front view sees at its place (0 on that surface)."""
    rows = np.clip(
        np.round((depth.top - vertices[:, 2]) / depth.pixel).astype(int), 0, depth.front.shape[0] - 1
    )
    columns = np.clip(
        np.round((vertices[:, 0] - depth.left) / depth.pixel).astype(int), 0, depth.front.shape[1] - 1
    )
    front = depth.front[rows, columns]
    behind = front - (-vertices[:, 1])
    return np.where(np.isfinite(behind), np.maximum(behind, 0.0), 0.0)
