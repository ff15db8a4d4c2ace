"""Verdicts on the numbers printed in the seeds."""

from __future__ import annotations

import pytest

from derivations import errata

EXPECTED = {
    "annotations.front_maple_delta": "correct",
    "annotations.front_maple_alpha": "correct",
    "annotations.front_maple_closed_form": "correct",
    "annotations.side_corner_dot": "correct",
    "dx11.rsm_vpls": "correct",
    "dx12.legendre_20": "correct",
    "annotations.front_maple_decimal": "rounded",
    "annotations.side_maple_closed_form": "correct",
    "annotations.side_maple_20_digits": "wrong",
    "annotations.side_maple_5_digits": "wrong",
    "annotations.front_integral_decimal": "wrong",
    "annotations.side_integral_decimal": "correct",
    "annotations.pixel_solid_angle": "approximate",
    "dx11.sh_c0": "rounded",
    "dx11.sh_c1": "rounded",
    "dx11.coslobe_c0": "correct",
    "dx11.coslobe_c1": "rounded",
    "dx11.pi": "truncated",
    "dx11.front_solid_angle": "correct",
    "dx11.side_solid_angle": "wrong",
    "dx11.front_weight": "wrong",
    "dx11.side_weight": "wrong",
    "dx11.side_eval_small": "truncated",
    "dx11.side_eval_big": "correct",
    "dx11.surfel_weight": "not derivable",
    "dx11.l1_accuracy": "wrong",
}


@pytest.mark.parametrize("key, verdict", sorted(EXPECTED.items()))
def test_verdicts(key, verdict):
    assert errata.check(key).verdict == verdict


def test_twenty_digit_value_is_wrong_in_its_last_digits():
    row = errata.check("annotations.side_maple_20_digits")
    assert row.exact_digits.startswith("0.42343135443673907673")
    assert row.correct_digits == 19
    assert row.relative_error == pytest.approx(-1.2e-19, rel=0.05)


def test_every_row_is_checked_and_rendered():
    table = errata.table()
    assert all(row.verdict in errata.VERDICTS for row in table)
    text = errata.markdown()
    assert text.count("\n") == len(table) + 2
    assert "0.4234413544" in text and "not derivable" in text


def test_unknown_key_lists_the_keys():
    with pytest.raises(KeyError, match="dx11.pi"):
        errata.check("dx11.tau")


def test_significant_digits():
    assert errata.significant_digits("0.0150") == 3
    assert errata.significant_digits("3.1415926") == 8
