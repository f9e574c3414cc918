"""Front-view depth maps of a mesh: how far forward (-Y) its surface comes at each point of a grid."""

from __future__ import annotations

import numpy as np


class DepthMap:
    """How far forward (-Y) the surface comes at each point of a front-view grid; NaN where no surface.

    Pixel (row, column) looks at x = left + column * pixel, z = top - row * pixel.
    """

    def __init__(self, vertices: np.ndarray, triangles: np.ndarray, pixel: float, like=None) -> None:
        """like: another DepthMap whose grid this one shares (to compare what two meshes show)."""
        self.pixel = pixel
        if like is not None:
            self.pixel, self.left, self.top = like.pixel, like.left, like.top
            rows, columns = like.front.shape
        else:
            used = vertices[np.unique(triangles)]
            self.left = used[:, 0].min() - 2 * pixel
            self.top = used[:, 2].max() + 2 * pixel
            columns = int(np.ceil((used[:, 0].max() + 2 * pixel - self.left) / pixel)) + 1
            rows = int(np.ceil((self.top - used[:, 2].min() + 2 * pixel) / pixel)) + 1
        self.front = self._rasterise(vertices, triangles, rows, columns)

    def _rasterise(self, vertices: np.ndarray, triangles: np.ndarray, rows: int, columns: int) -> np.ndarray:
        u = (vertices[:, 0] - self.left) / self.pixel
        v = (self.top - vertices[:, 2]) / self.pixel
        forward = -vertices[:, 1]
        tu, tv, tf = u[triangles], v[triangles], forward[triangles]
        # Clipped to the grid: a map sharing another's grid may hold triangles beyond it.
        u0 = np.maximum(np.ceil(tu.min(1)), 0).astype(np.int64)
        u1 = np.minimum(np.floor(tu.max(1)), columns - 1).astype(np.int64)
        v0 = np.maximum(np.ceil(tv.min(1)), 0).astype(np.int64)
        v1 = np.minimum(np.floor(tv.max(1)), rows - 1).astype(np.int64)
        span_u = np.clip(u1 - u0 + 1, 0, None)
        counts = span_u * np.clip(v1 - v0 + 1, 0, None)
        owner = np.repeat(np.arange(len(triangles)), counts)
        local = np.arange(owner.size) - np.repeat(np.cumsum(counts) - counts, counts)
        pu = u0[owner] + local % span_u[owner]
        pv = v0[owner] + local // span_u[owner]
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
        image = np.full(rows * columns, -np.inf)
        np.maximum.at(image, pv[inside] * columns + pu[inside], depth)
        image = image.reshape(rows, columns)
        image[~np.isfinite(image)] = np.nan
        return image

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
