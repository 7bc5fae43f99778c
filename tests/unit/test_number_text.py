"""timeseries.csv's numbers: the compiled formatter writes exactly the text Python's '%.12g' writes."""

from __future__ import annotations

import io

import numpy as np
import pytest

from pchute_exudyn.physics import compiled
from pchute_exudyn.results.number_text import LARGEST, SMALLEST, _python_rows, table_text

EDGES = [0.0, -0.0, np.nan, -np.nan, np.inf, -np.inf, 5e-324, 2.2250738585072014e-308, 1.7976931348623157e308,
         SMALLEST, LARGEST, np.nextafter(SMALLEST, 0.0), np.nextafter(LARGEST, np.inf),
         1e-5, 1e-4, 9.99999999999e-5, 9.9999999999949996e-05, 9.99999999999500e-05, 0.0001, 0.1, 0.3, 1 / 3, 2 / 3,
         0.5, 1.5, 2.5, 100.0, 12345.6789, 99.9999999999995, 0.00999999999999,
         123456789012.0, 1234567890123.0, 999999999999.5, 999999999999.4, 999999999999.6,
         1000000000005.0, 1000000000015.0, 1000000000025.0, 9999999999995.0, 1e11, 1e12, 1e16, 1e22, 1e100, 1e-100,
         *(10.0 ** k for k in range(-310, 309)), *(9.999999999995 * 10.0 ** k for k in range(-300, 300)),
         *(1.000000000005 * 10.0 ** k for k in range(-300, 300))]


def _python(values: np.ndarray, width: int) -> str:
    table = values[: len(values) // width * width].reshape(-1, width)
    return ",".join(f"c{i}" for i in range(width)) + "\n" + _python_rows(table)


def _compiled(values: np.ndarray, width: int) -> str:
    table = values[: len(values) // width * width].reshape(-1, width)
    return table_text([f"c{i}" for i in range(width)], list(table.T))


@pytest.mark.parametrize("source", ["bit patterns", "magnitudes", "edges"])
def test_the_compiled_text_is_pythons_to_the_character(source):
    rng = np.random.default_rng(11)
    if source == "bit patterns":   # every double equally likely: every exponent, subnormals, NaNs, infinities
        values = rng.integers(0, 2**64, size=200_000, dtype=np.uint64).view(np.float64)
    elif source == "magnitudes":   # what histories hold
        values = rng.uniform(-1.0, 1.0, 200_000) * 10.0 ** rng.integers(-8, 9, 200_000)
    else:
        values = np.array(EDGES + [-v for v in EDGES])
    for width in (1, 7):
        assert _compiled(values, width) == _python(values, width)


def test_the_text_is_what_numpy_savetxt_writes():
    rng = np.random.default_rng(3)
    columns = [rng.normal(size=500) * 10.0 ** rng.integers(-6, 9, 500) for _ in range(4)]
    buffer = io.StringIO()
    buffer.write("a,b,c,d\n")
    np.savetxt(buffer, np.column_stack(columns), delimiter=",", fmt="%.12g")
    assert table_text(list("abcd"), columns) == buffer.getvalue()


def test_a_row_with_a_value_left_to_python_is_written_by_python_and_the_others_compiled():
    """A tie (13 significant digits ending in 5) and a magnitude past the kernel's range send their rows to Python;
    every call ran compiled code."""
    compiled.FALLBACKS.clear()
    columns = [np.array([1.25, 1000000000005.0, 2.0, 1e300]), np.array([3.0, 4.0, 0.1, 5.0])]
    assert table_text(["x", "y"], columns) == "x,y\n1.25,3\n1e+12,4\n2,0.1\n1e+300,5\n"
    assert compiled.FALLBACKS == {}
