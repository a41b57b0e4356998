"""One table of the identified coefficients' names: ``core.names.COEFFICIENTS`` (issue #50).

The rig fits (identify), the campaign summaries and a vehicle file's ``uncertainty:`` block
(model) key the same three coefficients; each layer reads the one table, and the physics layers
hold no hand-written copy of it.
"""

from __future__ import annotations

import ast
from pathlib import Path

from hydrokit.core import names

SRC = Path(__file__).resolve().parents[2] / "src" / "hydrokit"
#: the layers below simulate/, where the table's users live next to it
LOWER_LAYERS = ("core", "identify", "estimate", "model")


def _hand_written_copies(path: Path) -> list[int]:
    """Lines of ``path`` holding a tuple, list or set literal of exactly the three names."""
    wanted = set(names.COEFFICIENTS)
    lines = []
    for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"))):
        if isinstance(node, (ast.Tuple, ast.List, ast.Set)) and len(node.elts) == len(wanted):
            values = {e.value for e in node.elts if isinstance(e, ast.Constant) and isinstance(e.value, str)}
            if values == wanted:
                lines.append(node.lineno)
    return lines


def test_the_table_is_the_order_of_a_fitted_parameter_vector():
    # (m_a, K_L, K_Q): the order of RigConstants.from_normalised and of the fit's covariance
    assert names.COEFFICIENTS == ("added_mass", "linear_damping", "quadratic_damping")


def test_model_uncertainty_keeps_its_public_name_for_the_one_table():
    from hydrokit.model import uncertainty

    assert uncertainty.COEFFICIENTS is names.COEFFICIENTS


def test_the_lower_layers_hold_no_hand_written_copy():
    found = {
        f"{path.relative_to(SRC)}:{line}"
        for layer in LOWER_LAYERS
        for path in sorted((SRC / layer).rglob("*.py"))
        for line in _hand_written_copies(path)
    }
    assert found == {f"core/names.py:{_hand_written_copies(SRC / 'core' / 'names.py')[0]}"}, sorted(found)


def test_the_scan_sees_a_copy_in_any_order(tmp_path):
    # the check above must be able to fail: a reordered list literal is still a copy
    module = tmp_path / "copy.py"
    module.write_text('KEYS = ["quadratic_damping", "added_mass", "linear_damping"]\nOTHER = ("added_mass",)\n')
    assert _hand_written_copies(module) == [1]
