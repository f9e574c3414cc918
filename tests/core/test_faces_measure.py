"""The figures that judge a key: folds of the mesh's edges."""

import numpy as np

from turkish_lipsync.core.faces.measure import edge_folds


def _sheet(size: int = 6):
    """A flat square sheet of size x size vertices in the XZ plane, two triangles per cell."""
    x, z = np.meshgrid(np.arange(size, dtype=np.float64), np.arange(size, dtype=np.float64))
    vertices = np.stack((x.ravel(), np.zeros(size * size), z.ravel()), axis=1)
    triangles = []
    for row in range(size - 1):
        for column in range(size - 1):
            corner = row * size + column
            triangles += [(corner, corner + 1, corner + size + 1), (corner, corner + size + 1, corner + size)]
    return vertices, np.array(triangles)


def test_a_sheet_folded_over_a_line_counts_the_edges_along_the_fold():
    vertices, triangles = _sheet()
    everywhere = np.ones(len(vertices), bool)
    above = vertices[:, 2] > 2.5
    folded = np.zeros_like(vertices)
    # The rows above z = 2.5 swing about the line z = 2.5 by 150 degrees, toward -Y.
    angle = np.radians(150)
    height = vertices[above, 2] - 2.5
    folded[above, 1] = -height * np.sin(angle)
    folded[above, 2] = 2.5 + height * np.cos(angle) - vertices[above, 2]
    # The hinge runs through the cells between the rows z = 2 and z = 3: their diagonals and the edges
    # across them bend, the flat halves on either side do not.
    count = edge_folds(triangles, vertices, folded, everywhere)
    assert count > 0
    assert edge_folds(triangles, vertices, folded, ~above) == 0  # the still half has no fold of its own
    assert edge_folds(triangles, vertices, folded, everywhere, degrees=170) == 0  # 150 degrees is less


def test_moving_or_turning_a_sheet_whole_folds_nothing():
    vertices, triangles = _sheet()
    everywhere = np.ones(len(vertices), bool)
    assert edge_folds(triangles, vertices, np.full_like(vertices, 0.3), everywhere) == 0
    turn = np.array([[0.0, -1.0, 0.0], [1.0, 0.0, 0.0], [0.0, 0.0, 1.0]])
    assert edge_folds(triangles, vertices, vertices @ turn.T - vertices, everywhere) == 0
    # A gentle bend (20 degrees over the whole sheet) is no fold.
    bent = np.zeros_like(vertices)
    bent[:, 1] = -0.02 * (vertices[:, 2] - 2.5) ** 2
    assert edge_folds(triangles, vertices, bent, everywhere) == 0
