"""The Fuzzy-PI's inference (sensors/controllers.py) is max-min over the whole rule table.

``fuzzy_increment`` only visits the rules that fire (at most four); here the
Mamdani definition is written out over all 49 rules and all seven output
terms, and the two must agree exactly.
"""

import numpy as np

from CadRobotWB.sensors import controllers


def mamdani_over_the_whole_table(error, change):
    """Every rule's strength, every term clipped at its strongest rule, merged, centroid."""
    def degrees(x):
        x = float(np.clip(x, -1.0, 1.0))
        return np.clip(1.0 - np.abs(x - controllers.TERM_CENTRES) / controllers.TERM_HALF_WIDTH,
                       0.0, 1.0)

    strengths = np.minimum.outer(degrees(error), degrees(change))               # (7, 7)
    term_strength = np.zeros(len(controllers.LABELS))
    np.maximum.at(term_strength, controllers.RULE_TABLE.ravel(), strengths.ravel())
    grid = controllers._OUTPUT_GRID
    shapes = np.clip(1.0 - np.abs(grid[None] - controllers.TERM_CENTRES[:, None])
                     / controllers.TERM_HALF_WIDTH, 0.0, None)                  # (7, G)
    merged = np.max(np.minimum(shapes, term_strength[:, None]), axis=0)
    return float(np.sum(merged * grid) / np.sum(merged))


def test_only_the_rules_that_fire_give_the_same_answer():
    centres = np.linspace(-1.0, 1.0, 7)
    inputs = np.concatenate([np.random.default_rng(0).uniform(-1.5, 1.5, (3000, 2)),
                             np.stack(np.meshgrid(centres, centres), -1).reshape(-1, 2)])
    for error, change in inputs:
        assert controllers.fuzzy_increment(error, change) == mamdani_over_the_whole_table(
            error, change), (error, change)
