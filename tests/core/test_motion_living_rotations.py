"""Rotations in the character's frame (core/motion/living/rotations.py): products over stacks of them."""

import numpy as np

from turkish_lipsync.core.motion.living.rotations import head_matrices, stack_product


def test_a_stack_product_is_the_matrix_product_of_every_matrix():
    rng = np.random.default_rng(4)
    stack, left, right = rng.normal(size=(37, 4, 4)), rng.normal(size=(4, 4)), rng.normal(size=(4, 4))
    assert np.allclose(stack_product(left, stack, right), left @ stack @ right)
    assert np.allclose(stack_product(None, stack[:, :3, :3], right[:3, :3]), stack[:, :3, :3] @ right[:3, :3])
    assert np.allclose(stack_product(left, stack), left @ stack)
    assert np.allclose(stack_product(None, stack), stack)
    rotations = head_matrices(rng.uniform(-20, 20, (37, 3)))
    turned = stack_product(rotations[0], rotations, rotations[0].T)
    assert np.allclose(turned @ turned.transpose(0, 2, 1), np.eye(3))  # a rotation seen in another frame
