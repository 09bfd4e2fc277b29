"""The slack/wrinkle indicator of the membrane in space: signs of the principal stresses."""

import numpy as np

from fabric_dolfinx.part.fields import slack_indicator


def test_taut_wrinkled_and_slack_cells_are_told_apart():
    stresses = np.array(
        [
            [[1.0, 0.5], [0.5, 1.0]],  # principal 1.5, 0.5: taut
            [[1.0, 0.0], [0.0, -1e-3]],  # one compressive: wrinkled
            [[0.1, 0.4], [0.4, 0.1]],  # principal 0.5, -0.3 (shear dominated): wrinkled
            [[-1.0, 0.0], [0.0, -2.0]],  # both compressive: slack
            [[0.0, 0.0], [0.0, 0.0]],  # unstressed: slack
        ]
    )
    np.testing.assert_array_equal(slack_indicator(stresses), [0, 1, 1, 2, 2])
    # congruence (S -> F S F^T) keeps the answer
    F = np.array([[1.3, 0.2], [-0.1, 0.8]])
    congruent = np.einsum("ij,njk,lk->nil", F, stresses, F)
    np.testing.assert_array_equal(slack_indicator(congruent), slack_indicator(stresses))
