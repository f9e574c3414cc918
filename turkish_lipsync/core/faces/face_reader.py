"""Reading a face off a front-view depth map: nose, lips and chin on the midline, the mouth corners along
the crease between the lips, the eyes in their sockets (or the eyeballs showing between the lids), the
brows above them."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..base.errors import HeadError
from .depth import DepthMap, box_blur

# An eye's opening and upper lid reach at most this far above its corners (face sizes).
EYE_HEIGHT = 0.05
# Under the chin the profile falls back more than UNDER_CHIN_FALL within UNDER_CHIN_RUN (face sizes).
UNDER_CHIN_FALL = 0.04
UNDER_CHIN_RUN = 0.02


@dataclass(frozen=True, eq=False)
class _Socket:
    """An eye socket in the depth map: the window it was sought in (rows top..bottom, columns
    first..last), its bowl depth there, its deepest pixel and its outline (pixels of the window)."""

    side: str
    direction: int  # +1 left of the middle (+X), -1 right
    top: int
    bottom: int
    first: int
    last: int
    depth: np.ndarray
    seed: tuple
    rows: np.ndarray
    columns: np.ndarray


class FaceReader:
    """Reads the face off a depth map: nose, lips and chin on the midline, then mouth corners, eyes, brows."""

    def __init__(self, depth: DepthMap, size: float, others: DepthMap | None = None) -> None:
        self.depth = depth
        # Where another piece (an eyeball) shows in front of the skin, or through a hole in it.
        self.showing = np.zeros(depth.front.shape, bool)
        if others is not None:
            with np.errstate(invalid="ignore"):
                self.showing = np.isfinite(others.front) & ~(depth.front > others.front + 0.002 * size)
        self.size = size
        front = depth.front
        valid = np.isfinite(front)
        if valid.sum() < 100:
            raise HeadError("The head mesh covers too little of the front view to find a face.")
        # Holes (eye and mouth openings of a mask) count as deep recesses.
        self.floor = np.nanmin(front) - 0.05 * size
        self.filled = np.where(valid, front, self.floor)
        self.valid = valid
        self.groove = self._groove_strength()

    def pixels(self, fraction: float) -> int:
        return max(1, int(round(fraction * self.size / self.depth.pixel)))

    def landmarks(self) -> dict[str, np.ndarray]:
        nose_row, mid = self.nose_tip()
        mouth_row = self.mouth_line(nose_row, mid)
        points = {"nose_tip": self.depth.point(nose_row, mid)}
        points.update(self.midline(nose_row, mouth_row, mid))
        points.update(self.mouth_corners(mouth_row, mid))
        points.update(self.eyes_and_brows(nose_row, mid))
        return points

    def nose_tip(self) -> tuple[int, int]:
        """The most forward point near the vertical midline, between the forehead and the jaw."""
        rows = np.flatnonzero(self.valid.any(1))
        columns = np.flatnonzero(self.valid.any(0))
        centre = (columns[0] + columns[-1]) // 2
        half = self.pixels(0.04)
        top = rows[0] + int(0.25 * (rows[-1] - rows[0]))
        bottom = rows[0] + int(0.85 * (rows[-1] - rows[0]))
        window = np.where(self.valid, self.depth.front, -np.inf)[
            top:bottom, centre - half : centre + half + 1
        ]
        if not np.isfinite(window).any():
            raise HeadError("No surface faces -Y near the middle of the head; turn the face toward -Y.")
        row, column = np.unravel_index(np.argmax(window), window.shape)
        return top + int(row), centre - half + int(column)

    def _groove_strength(self) -> np.ndarray:
        """How much deeper each pixel is than the pixels a little above and below it (a horizontal crease)."""
        padded = np.pad(self.filled, ((3, 3), (0, 0)), mode="edge")
        rows = self.filled.shape[0]
        strength = np.zeros_like(self.filled)
        for step in (1, 2, 3):
            above = padded[3 - step : 3 - step + rows]
            below = padded[3 + step : 3 + step + rows]
            strength = np.maximum(strength, np.minimum(above, below) - self.filled)
        return strength

    def _bowl_depth(self, reach: int) -> np.ndarray:
        """How far a pixel lies below its surroundings both vertically and sideways: a socket or an opening.

        A crease or the side of the nose is low in one direction only, so it scores nothing.
        """
        padded = np.pad(self.filled, reach, mode="edge")
        rows, columns = self.filled.shape
        vertical = np.zeros_like(self.filled)
        sideways = np.zeros_like(self.filled)
        for step in np.unique(np.linspace(1, reach, 8).astype(int)):
            up = padded[reach - step : reach - step + rows, reach : reach + columns]
            down = padded[reach + step : reach + step + rows, reach : reach + columns]
            left = padded[reach : reach + rows, reach - step : reach - step + columns]
            right = padded[reach : reach + rows, reach + step : reach + step + columns]
            vertical = np.maximum(vertical, np.minimum(up, down) - self.filled)
            sideways = np.maximum(sideways, np.minimum(left, right) - self.filled)
        return np.minimum(vertical, sideways)

    def follow_crease(self, row: int, column: int, direction: int, threshold: float, steps: int):
        """Walk sideways along a horizontal crease while it stays deeper than threshold; its last pixel."""
        last = (row, column)
        weak = 0
        height, width = self.groove.shape
        for _ in range(steps):
            column += direction
            if not 2 <= column < width - 2:
                break
            window = self.groove[max(row - 2, 0) : row + 3, column]
            best = int(np.argmax(window))
            if window[best] < threshold:
                weak += 1
                if weak >= 2:
                    break
                continue
            weak = 0
            row = max(row - 2, 0) + best
            last = (row, column)
        return last

    def mouth_line(self, nose_row: int, mid: int) -> int:
        """The row of the crease (or gap) between the lips, the strongest horizontal groove under the nose."""
        first = nose_row + self.pixels(0.04)
        last = min(nose_row + self.pixels(0.3), self.filled.shape[0] - 1)
        if last <= first:
            raise HeadError("The head mesh ends just below the nose; no mouth was found under it.")
        half = self.pixels(0.03)
        strength = self.groove[first:last, max(mid - half, 0) : mid + half + 1]
        score = np.median(np.minimum(strength, 0.02 * self.size), axis=1)
        if score.max() <= 1e-4 * self.size:
            raise HeadError(
                "No mouth found under the nose (no crease or gap between lips facing -Y). Turn the head so "
                "its face looks toward -Y with Z up (Blender's front view), or place the landmark markers."
            )
        return first + int(np.argmax(score))

    def midline(self, nose_row: int, mouth_row: int, mid: int) -> dict[str, np.ndarray]:
        """Lips, their contact line and the chin on the vertical profile through the nose tip."""
        profile = self.filled[:, mid - 1 : mid + 2].max(1)
        reach = self.pixels(0.05)
        upper = mouth_row - reach + int(np.argmax(profile[mouth_row - reach : mouth_row]))
        lower = mouth_row + 1 + int(np.argmax(profile[mouth_row + 1 : mouth_row + reach + 1]))
        # Behind the lips by more than a few millimetres is the inside of the mouth (or a hole): the gap.
        gap_depth = min(profile[upper], profile[lower]) - 0.02 * self.size
        upper_inner = mouth_row
        while upper_inner > upper + 1 and profile[upper_inner] < gap_depth:
            upper_inner -= 1
        lower_inner = mouth_row
        while lower_inner < lower - 1 and profile[lower_inner] < gap_depth:
            lower_inner += 1
        if profile[mouth_row] < gap_depth:
            upper_inner = min(upper_inner, mouth_row - 1)
            lower_inner = max(lower_inner, mouth_row + 1)
        column_rows = np.flatnonzero(self.valid[:, mid])
        end = min(nose_row + self.pixels(0.45), column_rows[-1])
        start = lower + self.pixels(0.03)
        # Under the chin the surface turns to face down: the profile falls back faster than it descends,
        # and keeps falling (the groove under a full lower lip falls steeply too, but only millimetres).
        rows = np.arange(start, end + 1)
        ahead = profile[np.minimum(rows + self.pixels(UNDER_CHIN_RUN), end)] - profile[rows]
        steep = np.diff(profile[rows]) < -1.5 * self.depth.pixel
        falls = np.flatnonzero(steep & (ahead[:-1] < -UNDER_CHIN_FALL * self.size))
        if falls.size:
            end = start + int(falls[0])
        if end <= start:
            raise HeadError("The head mesh ends below the lower lip: no chin was found. Include the chin.")
        # The chin is the most forward point below the groove under the lower lip; a receding chin with
        # no groove: where a line from the lower lip first touches the profile below (its support point).
        below = np.arange(start, end + 1)
        values = profile[below]
        dip_before = np.minimum.accumulate(values)
        bulges = below[
            (values - dip_before > 0.001 * self.size) & (values >= np.maximum.accumulate(values[::-1])[::-1])
        ]
        if bulges.size:
            chin = int(bulges[0])
        else:
            chin = int(below[np.argmax((values - profile[lower]) / (below - lower))])
        point = self.depth.point
        return {
            "upper_lip": point(upper, mid),
            "lower_lip": point(lower, mid),
            "upper_lip_inner": point(upper_inner, mid),
            "lower_lip_inner": point(lower_inner, mid),
            "chin": point(chin, mid),
        }

    def mouth_corners(self, mouth_row: int, mid: int) -> dict[str, np.ndarray]:
        """Follow the crease between the lips sideways from the midline until it fades: the mouth corners."""
        # A gap between parted lips is far deeper than the crease near the corners: cap the reference.
        reference = min(
            np.median(self.groove[mouth_row - 1 : mouth_row + 2, mid - 2 : mid + 3].max(0)), 0.006 * self.size
        )
        steps = self.pixels(0.16)
        corners = {}
        for name, direction in (("mouth_corner_left", 1), ("mouth_corner_right", -1)):
            row, column = self.follow_crease(mouth_row, mid, direction, 0.25 * reference, steps)
            corners[name] = self._surface_near(row, column)
        return corners

    def eyes_and_brows(self, nose_row: int, mid: int) -> dict[str, np.ndarray]:
        """The eyes are the sockets on each side above the nose tip; the brows the ridge above them."""
        top = max(nose_row - self.pixels(0.3), 1)
        bottom = nose_row - self.pixels(0.04)
        bowl = self._bowl_depth(self.pixels(0.06))
        recess = box_blur(self.filled, self.pixels(0.04)) - self.filled
        points = {}
        for side, direction in (("left", 1), ("right", -1)):
            socket = self._eye_socket(side, direction, top, bottom, mid, bowl, recess)
            inner, outer = self._eye_corners(socket, mid, points)
            points[f"eye_inner_{side}"] = self._surface_near(*inner)
            points[f"eye_outer_{side}"] = self._surface_near(*outer)
            centre_column = (inner[1] + outer[1]) // 2
            # The socket's recess may run on up a flat forehead: the eye ends a little above its corners.
            corners_row = min(inner[0], outer[0])
            eye_top = min(corners_row, max(top + socket.rows.min(), corners_row - self.pixels(EYE_HEIGHT)))
            brow_rows = np.arange(max(eye_top - self.pixels(0.1), 0), eye_top)
            brow_row = int(brow_rows[np.argmax(self.filled[brow_rows, centre_column])])
            points[f"brow_{side}"] = self.depth.point(brow_row, centre_column)
        return points

    def _eye_socket(
        self, side: str, direction: int, top: int, bottom: int, mid: int, bowl: np.ndarray, recess: np.ndarray
    ) -> _Socket:
        """The eye socket beside the nose on one side: its deepest point and its outline."""
        near, far = mid + direction * self.pixels(0.03), mid + direction * self.pixels(0.26)
        first, last = max(min(near, far), 0), max(near, far)
        depth = bowl[top:bottom, first : last + 1]
        if depth.size == 0 or depth.max() <= 0.002 * self.size:
            raise HeadError(
                f"No {side} eye found beside the nose (no socket where an eye should be). "
                "Turn the head so its face looks toward -Y with Z up, or place the landmark markers."
            )
        seed = np.unravel_index(np.argmax(depth), depth.shape)
        window = recess[top:bottom, first : last + 1]
        blob = _grow_blob(window > min(0.015 * self.size, 0.5 * window[seed]), seed)
        rows, columns = np.nonzero(blob)
        if rows.size == 0:
            raise HeadError(
                f"No {side} eye found beside the nose (its socket is too shallow to outline). "
                "Turn the head so its face looks toward -Y with Z up, or place the landmark markers."
            )
        return _Socket(side, direction, top, bottom, first, last, depth, seed, rows, columns)

    def _eye_corners(self, socket: _Socket, mid: int, points: dict) -> tuple:
        """The eye's (inner, outer) corner pixels: the ends of the eyeball seen through the lids (their
        margins go into points), else where the crease between the lids fades, else (closed, smooth
        eyes) where faces put them."""
        top, direction, rows = socket.top, socket.direction, socket.rows
        distance = np.abs(socket.first + socket.columns - mid)
        inner_column, outer_column = distance.min(), distance.max()
        inner_row = top + int(np.median(rows[distance == inner_column]))
        outer_row = top + int(np.median(rows[distance == outer_column]))
        # The opening narrows below a pixel toward the corners; its crease goes on to where the lids meet.
        threshold, steps = 0.004 * self.size, self.pixels(0.04)
        inner = self.follow_crease(
            inner_row, mid + direction * int(inner_column), -direction, threshold, steps
        )
        outer = self.follow_crease(
            outer_row, mid + direction * int(outer_column), direction, threshold, steps
        )
        opening = self._eye_opening(top, socket.bottom, socket.first, socket.last, socket.seed, mid)
        if opening is not None:
            # The lids' margins above and below the middle of the opening, where a blink meets.
            upper_margin, lower_margin = self.lid_margins
            points[f"upper_lid_{socket.side}"] = self.depth.point(*upper_margin)
            points[f"lower_lid_{socket.side}"] = self.depth.point(*lower_margin)
            return opening
        if socket.depth[socket.seed] < 0.01 * self.size or abs(outer[1] - inner[1]) < self.pixels(0.07):
            # Closed, smooth eyes (a low-poly mask): no opening or crease to read the corners from.
            # Faces put the eye centres about a fifth of the face's width either side of the middle,
            # and an eye is about as wide as the distance from its centre to the middle.
            row = top + int(socket.seed[0])
            covered = np.flatnonzero(self.valid[row])
            centre = 0.2 * (covered[-1] - covered[0])
            inner = (row, mid + direction * int(round(0.5 * centre)))
            outer = (row, mid + direction * int(round(1.5 * centre)))
        return inner, outer

    def _eye_opening(self, top: int, bottom: int, first: int, last: int, seed, mid: int) -> tuple | None:
        """(inner, outer) corner pixels of the eyeball seen through the lids, nearest the socket's
        deepest point; None when no separate eyeball shows there (eyes of the skin, or painted)."""
        window = self.showing[top:bottom, first : last + 1]
        if window.sum() < 8:
            return None
        rows, columns = np.nonzero(window)
        nearest = np.argmin((rows - seed[0]) ** 2 + (columns - seed[1]) ** 2)
        blob = _grow_blob(window, (rows[nearest], columns[nearest]))
        rows, columns = np.nonzero(blob)
        touches_border = rows.min() == 0 or columns.min() == 0
        touches_border |= rows.max() == window.shape[0] - 1 or columns.max() == window.shape[1] - 1
        if np.ptp(columns) < self.pixels(0.05) or touches_border:
            return None  # too small for an eye, or a sheet over the face (clothing helpers), not an eyeball
        ends = [
            (top + int(np.median(rows[columns == end])), first + int(end))
            for end in (columns.min(), columns.max())
        ]
        centre = (columns.min() + columns.max()) // 2
        margins = rows[columns == centre]
        self.lid_margins = (
            (top + int(margins.min()) - 1, first + centre),
            (top + int(margins.max()) + 1, first + centre),
        )
        return tuple(sorted(ends, key=lambda end: abs(end[1] - mid)))

    def _surface_near(self, row: int, column: int) -> np.ndarray:
        """The pixel's point on the bottom of its crease: skin around it, not the inside of an opening."""
        reach = self.pixels(0.006)
        patch = self.filled[
            max(row - reach, 0) : row + reach + 1, max(column - reach, 0) : column + reach + 1
        ]
        rim = patch.max()
        skin = patch[patch >= rim - 0.02 * self.size]
        return np.array([self.depth.x_of(column), -skin.min(), self.depth.z_of(row)])


def _grow_blob(mask: np.ndarray, seed: tuple[int, int]) -> np.ndarray:
    """The 4-connected region of a boolean mask that contains the seed pixel (grown at most twice the
    map's rows and columns in steps: a region winding further, which no eye or socket does, is cut)."""
    blob = np.zeros_like(mask)
    blob[seed] = True
    for _ in range(2 * sum(mask.shape)):
        grown = blob.copy()
        grown[1:] |= blob[:-1]
        grown[:-1] |= blob[1:]
        grown[:, 1:] |= blob[:, :-1]
        grown[:, :-1] |= blob[:, 1:]
        grown &= mask
        if np.array_equal(grown, blob):
            break
        blob = grown
    return blob
