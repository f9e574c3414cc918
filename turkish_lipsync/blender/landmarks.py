"""Face landmarks as empties the user can move before the shape keys are built.

The automatic landmarks are a guess; on an unusual head the user corrects them in the viewport. The
markers are children of the head, so they follow it; the builder reads them back in the head's own
coordinates, whatever the head's transform.
"""

from __future__ import annotations

from collections.abc import Mapping

import bpy
import numpy as np
from mathutils import Matrix, Vector

MARKER_PREFIX = "TR_landmark_"
COLLECTION_NAME = "TR Landmarks"
# Custom property holding the landmark name: object names may get ".001" when several heads have markers.
LANDMARK_PROPERTY = "turkish_lipsync_landmark"


def _markers_of(head: bpy.types.Object) -> list[bpy.types.Object]:
    return [child for child in head.children if LANDMARK_PROPERTY in child.keys()]


def _delete_markers(head: bpy.types.Object) -> int:
    markers = _markers_of(head)
    for marker in markers:
        bpy.data.objects.remove(marker, do_unlink=True)
    return len(markers)


def remove_landmark_markers(head: bpy.types.Object) -> int:
    """Delete the head's markers (and the collection once it is empty); how many were removed."""
    count = _delete_markers(head)
    collection = bpy.data.collections.get(COLLECTION_NAME)
    if collection is not None and not collection.objects and not collection.children:
        bpy.data.collections.remove(collection)
    return count


def _marker_collection(scene: bpy.types.Scene) -> bpy.types.Collection:
    collection = bpy.data.collections.get(COLLECTION_NAME)
    if collection is None:
        collection = bpy.data.collections.new(COLLECTION_NAME)
    if collection.name not in scene.collection.children and not _is_linked(scene.collection, collection):
        scene.collection.children.link(collection)
    return collection


def _is_linked(parent: bpy.types.Collection, collection: bpy.types.Collection) -> bool:
    return any(child == collection or _is_linked(child, collection) for child in parent.children)


def show_landmark_markers(
    head: bpy.types.Object,
    landmarks: Mapping[str, np.ndarray],
    scene: bpy.types.Scene | None = None,
) -> list[bpy.types.Object]:
    """Empties named TR_landmark_<name> at the landmarks (head-local coordinates), parented to the head.

    Running it again replaces the head's markers. They live in the "TR Landmarks" collection.
    """
    _delete_markers(head)
    scene = scene or bpy.context.scene
    collection = _marker_collection(scene)
    points = np.array([np.asarray(point, np.float64) for point in landmarks.values()])
    # Marker size: a small fraction of the face, in world units (the head's scale applies to children).
    world_scale = max(head.matrix_world.to_scale())
    spread = float(np.linalg.norm(np.ptp(points, axis=0))) if len(points) > 1 else 1.0
    display_size = 0.025 * spread * world_scale
    markers = []
    for name, point in landmarks.items():
        marker = bpy.data.objects.new(MARKER_PREFIX + name, None)
        marker.empty_display_type = "SPHERE"
        marker[LANDMARK_PROPERTY] = name
        collection.objects.link(marker)
        marker.parent = head
        marker.matrix_parent_inverse = Matrix.Identity(4)
        marker.location = Vector(np.asarray(point, np.float64).tolist())
        # Keep the sphere round and of the same size on screen whatever the head's scale.
        head_scale = head.matrix_world.to_scale()
        marker.scale = Vector([1.0 / component if component else 1.0 for component in head_scale])
        marker.empty_display_size = display_size
        markers.append(marker)
    return markers


def read_landmark_markers(head: bpy.types.Object) -> dict[str, np.ndarray] | None:
    """The markers' positions in the head's local coordinates, or None when the head has none."""
    markers = _markers_of(head)
    if not markers:
        return None
    # From the parent relation rather than matrix_world, which is stale until the depsgraph updates.
    return {
        str(marker[LANDMARK_PROPERTY]): np.array(
            (marker.matrix_parent_inverse @ marker.matrix_basis).translation, np.float64
        )
        for marker in markers
    }
