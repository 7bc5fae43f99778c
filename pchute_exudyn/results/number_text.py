"""Numbers as the text ``'%.12g' % x`` gives, for a whole table in one compiled call (timeseries.csv).

Python formats a float in about 0.3 us: for MER case 1's 6001 x 59 values that is 0.1 s, half a warm run's time
around its solve. The kernel here writes the same characters: the value correctly rounded to 12 significant digits
(round half to even, as C's and Python's formatting do), then C's ``%g`` layout (fixed notation for decimal exponents
-4 to 11, else ``d.ddde+XX``; trailing zeros and a bare point removed; ``nan``, ``inf``, ``-0``).

The rounding is exact where it claims to be: x times 10^k is formed in double-double arithmetic (an error below
2^-100 of the value) from a table of 10^k as pairs of doubles, and a value whose scaled fraction lies within 1e-6 of
one half (a tie, or too close to one to decide) is left to Python, as is any value outside 1e-280 to 1e290 in
magnitude; the caller formats those rows with Python (``table_text``). ``tests/unit/test_number_text.py`` compares the
two on 400 000 random values (any bit pattern, and numbers of every magnitude from 1e-8 to 1e8) and on the cases at
every boundary.
"""

from __future__ import annotations

import math

import numpy as np

from ..physics.compiled import COMPILED, kernel

POWER_RANGE = 320
"""10^k is tabled for k in -POWER_RANGE..POWER_RANGE (the fast path needs -279..292; beyond 300, zeros)."""
SMALLEST, LARGEST = 1e-280, 1e290
"""Magnitudes formatted by the kernel (Dekker's splits of x and of 10^k stay finite and exact)."""
WIDTH = 20
"""Characters a value takes at most, its delimiter included ('-1.23456789012e+308,')."""
_powers = None


def powers() -> tuple[np.ndarray, np.ndarray]:
    """10^k for k = -POWER_RANGE..POWER_RANGE as (high, low) doubles whose sum is 10^k to about 2^-106 relative."""
    global _powers
    if _powers is None:
        high, low = np.zeros(2 * POWER_RANGE + 1), np.zeros(2 * POWER_RANGE + 1)
        for i, k in enumerate(range(-POWER_RANGE, POWER_RANGE + 1)):
            if abs(k) > 300:   # never used (the fast path needs -280..292): kept out of double range's ends
                continue
            high[i], low[i] = _power_pair(k)
        _powers = high, low
    return _powers


def _power_pair(k: int) -> tuple[float, float]:
    """10^k as (high, low): high the double nearest 10^k, low the double nearest 10^k - high. Integer arithmetic
    only (Python's int / int is correctly rounded, as float(Fraction) is; Fractions took 11 ms for the table)."""
    numerator, denominator = (10 ** k, 1) if k >= 0 else (1, 10 ** -k)
    high = numerator / denominator
    top, bottom = high.as_integer_ratio()   # high exactly
    return high, (numerator * bottom - top * denominator) / (denominator * bottom)


def table_text(names, columns) -> str:
    """A CSV table: the header ``names``, then one row per sample of ``columns`` (arrays of one length), each value
    as '%.12g' formats it: by the compiled kernel, rows it leaves to Python (a tie, an extreme magnitude) and every
    row when the kernels run as Python, by Python."""
    table = np.ascontiguousarray(np.column_stack(columns) if columns else np.zeros((0, 0)), float)
    header = ",".join(names) + "\n"
    if not COMPILED or table.size == 0:
        return header + _python_rows(table)
    high, low = powers()
    out = np.empty(table.size * WIDTH + len(table), np.uint8)
    ends = np.zeros(len(table) + 1, np.int64)
    left = np.zeros(len(table), np.bool_)
    format_rows(table, high, low, out, ends, left)
    text = out[:ends[-1]].tobytes().decode("ascii")
    if not left.any():
        return header + text
    rows = [text[ends[i]:ends[i + 1]] if not left[i] else _python_rows(table[i:i + 1]) for i in range(len(table))]
    return header + "".join(rows)


def _python_rows(table: np.ndarray, block: int = 10000) -> str:
    """The rows formatted by Python, a block of rows in one operation (bounds the memory of a long history)."""
    row = ",".join(["%.12g"] * table.shape[1]) + "\n"
    return "".join((row * len(part)) % tuple(part.ravel().tolist())
                   for part in (table[start:start + block] for start in range(0, len(table), block)))


@kernel
def format_rows(table, high, low, out, ends, left):
    """Write each row of ``table`` as '%.12g' values separated by commas and ended by a newline into ``out``
    (bytes); row i spans ends[i]:ends[i + 1]. A row with a value the kernel does not decide is marked in ``left``
    (its text is then to be replaced)."""
    position = 0
    for i in range(table.shape[0]):
        for j in range(table.shape[1]):
            if j > 0:
                out[position] = 44   # ','
                position += 1
            written = _format_value(table[i, j], high, low, out, position)
            if written < 0:
                left[i] = True
            else:
                position = written
        out[position] = 10   # '\n'
        position += 1
        ends[i + 1] = position
    return position


@kernel
def _split(x):
    """Veltkamp's split: (high, low) halves of ``x`` whose products are exact."""
    t = 134217729.0 * x
    high = t - (t - x)
    return high, x - high


@kernel
def _scaled(x, high, low):
    """x (10^k as high + low) as a double-double (value, error): Dekker's exact product plus x low."""
    product = x * high
    xh, xl = _split(x)
    hh, hl = _split(high)
    error = ((xh * hh - product) + xh * hl + xl * hh) + xl * hl + x * low
    total = product + error
    return total, error - (total - product)


@kernel
def _write_digits(out, position, number, count):
    """The ``count`` decimal digits of ``number`` (leading zeros kept)."""
    for k in range(count - 1, -1, -1):
        quotient = number // 10
        out[position + k] = 48 + number - 10 * quotient
        number = quotient
    return position + count


@kernel
def _power_of_ten(count):
    """10^count as an integer (count >= 0)."""
    value = 1
    for _ in range(count):
        value *= 10
    return value


@kernel
def _format_value(x, high, low, out, position):
    """Write '%.12g' % x at ``position``; the position after it, or -1 when the value is left to Python."""
    if x != x:   # 'nan', whatever its sign
        out[position], out[position + 1], out[position + 2] = 110, 97, 110
        return position + 3
    if x < 0.0 or (x == 0.0 and math.copysign(1.0, x) < 0.0):
        out[position] = 45   # '-'
        position += 1
        x = -x
    if x == math.inf:
        out[position], out[position + 1], out[position + 2] = 105, 110, 102
        return position + 3
    if x == 0.0:
        out[position] = 48
        return position + 1
    if x < SMALLEST or x > LARGEST:
        return -1
    digits, exponent = _rounded(x, high, low)
    if digits < 0:
        return -1
    return _layout(out, position, digits, exponent)


@kernel
def _rounded(x, high, low):
    """(the 12 significant digits of x > 0 rounded half to even, as an integer, its decimal exponent); (-1, 0)
    when the rounding is left to Python (a tie or too near one)."""
    exponent = int(math.floor(math.log10(x)))
    for _ in range(3):   # the estimate can be one off either way
        k = 11 - exponent
        value, error = _scaled(x, high[k + POWER_RANGE], low[k + POWER_RANGE])
        whole = math.floor(value)
        fraction = (value - whole) + error
        if abs(fraction - 0.5) < 1e-6:
            return -1, 0
        digits = int(whole) + (1 if fraction > 0.5 else 0)
        if digits < 100000000000:
            exponent -= 1
        elif digits > 1000000000000:
            exponent += 1
        elif digits == 1000000000000:   # rounded up to the next power of ten
            return 100000000000, exponent + 1
        else:
            return digits, exponent
    return -1, 0


@kernel
def _layout(out, position, digits, exponent):
    """C's %g layout of the 12 digits ``digits`` times 10^(exponent - 11) at ``position``; the position after."""
    significant = 12
    quotient = digits // 10
    while digits == 10 * quotient:   # trailing zeros off
        digits, quotient = quotient, quotient // 10
        significant -= 1
    if -4 <= exponent < 12:   # fixed notation
        if exponent < 0:
            out[position], out[position + 1] = 48, 46   # '0.'
            for k in range(-exponent - 1):
                out[position + 2 + k] = 48
            return _write_digits(out, position + 1 - exponent, digits, significant)
        whole_digits = exponent + 1
        if significant <= whole_digits:
            position = _write_digits(out, position, digits, significant)
            for k in range(whole_digits - significant):
                out[position + k] = 48
            return position + whole_digits - significant
        scale = _power_of_ten(significant - whole_digits)
        position = _write_digits(out, position, digits // scale, whole_digits)
        out[position] = 46   # '.'
        return _write_digits(out, position + 1, digits % scale, significant - whole_digits)
    scale = _power_of_ten(significant - 1)
    position = _write_digits(out, position, digits // scale, 1)
    if significant > 1:
        out[position] = 46
        position = _write_digits(out, position + 1, digits % scale, significant - 1)
    out[position] = 101   # 'e'
    out[position + 1] = 43 if exponent >= 0 else 45
    magnitude = abs(exponent)
    return _write_digits(out, position + 2, magnitude, 2 if magnitude < 100 else 3)
