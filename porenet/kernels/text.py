"""Reading whitespace-separated numbers from text at memory speed (the Statoil network files,
:mod:`porenet.kinds.network.files`).

numpy's text parsers (``numpy.loadtxt``, ``numpy.fromstring``) cost ~300 ns a number here,
~20 s for the ~60 million numbers of a million-pore Statoil network. :func:`parse_numbers`
reads them in one compiled pass over the bytes and keeps the line structure (how many numbers
each line holds, and its line number), which files with lines of different lengths need.

Every value is the correctly rounded double of its text, as Python's ``float`` gives it: a
number whose digits fit in 53 bits and whose decimal exponent is at most 22 in magnitude
(every number written with up to 15 significant digits and an exponent within ±22 after
removing the point: all of pnextract's output) is one exact integer multiplied or divided by
one exact power of ten, a single correctly rounded operation (Clinger's fast path); any
other token (more digits, a larger exponent, ``nan``, a Fortran ``1.0D-05``) is handed to
``float`` afterwards, so the result never depends on the path.
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np

from porenet.jit.jit import njit

#: Exact powers of ten as doubles (10**22 is the largest that is exact).
_POW10 = np.array([10.0**k for k in range(23)])
#: Largest integer every smaller one of which is exact in a double.
_MAX_EXACT = 2**53


class Numbers(NamedTuple):
    """The numbers of a text, line by line.

    Attributes
    ----------
    values : ndarray of float64, shape (K,)
        Every number, in the order of the text.
    counts : ndarray of int64, shape (L,)
        How many numbers each line that holds any has (blank lines are skipped).
    lines : ndarray of int64, shape (L,)
        The (1-based) line number of each of those lines.
    """

    values: np.ndarray
    counts: np.ndarray
    lines: np.ndarray


@njit
def _is_space(c: int) -> bool:
    return c == 32 or c == 9 or c == 13 or c == 11 or c == 12


@njit
def _count(buf: np.ndarray) -> tuple[int, int]:
    """Tokens and non-blank lines of ``buf``."""
    tokens = 0
    lines = 0
    in_token = False
    line_open = False
    for i in range(buf.shape[0]):
        c = buf[i]
        if c == 10:
            in_token = False
            line_open = False
        elif _is_space(c):
            in_token = False
        elif not in_token:
            in_token = True
            tokens += 1
            if not line_open:
                line_open = True
                lines += 1
    return tokens, lines


@njit
def _fill(
    buf: np.ndarray,
    pow10: np.ndarray,
    values: np.ndarray,
    counts: np.ndarray,
    lines: np.ndarray,
    slow: np.ndarray,
) -> int:
    """Parse every token of ``buf`` into ``values`` and the line structure into ``counts`` and
    ``lines``; tokens off the fast path are left NaN, and the first ``len(slow)`` of them are
    listed in ``slow`` (rows ``token, start, stop``: index and byte range). Returns the number
    of slow tokens."""
    n = buf.shape[0]
    i = 0
    line = 1
    row = -1
    line_open = False
    tok = 0
    n_slow = 0
    while i < n:
        c = buf[i]
        if c == 10:
            line += 1
            line_open = False
            i += 1
            continue
        if _is_space(c):
            i += 1
            continue
        if not line_open:
            row += 1
            counts[row] = 0
            lines[row] = line
            line_open = True
        start = i
        negative = False
        if c == 45 or c == 43:  # '-' '+'
            negative = c == 45
            i += 1
        mantissa = 0
        exponent = 0
        digits = 0
        exact = True
        while i < n and 48 <= buf[i] <= 57:
            if mantissa <= _MAX_EXACT:
                mantissa = mantissa * 10 + (buf[i] - 48)
            else:
                exact = False
            digits += 1
            i += 1
        if i < n and buf[i] == 46:  # '.'
            i += 1
            while i < n and 48 <= buf[i] <= 57:
                if mantissa <= _MAX_EXACT:
                    mantissa = mantissa * 10 + (buf[i] - 48)
                    exponent -= 1
                else:
                    exact = False
                digits += 1
                i += 1
        if digits > 0 and i < n and (buf[i] == 101 or buf[i] == 69):  # 'e' 'E'
            j = i + 1
            exp_negative = False
            if j < n and (buf[j] == 45 or buf[j] == 43):
                exp_negative = buf[j] == 45
                j += 1
            e = 0
            e_digits = 0
            while j < n and 48 <= buf[j] <= 57:
                if e < 100000:
                    e = e * 10 + (buf[j] - 48)
                e_digits += 1
                j += 1
            if e_digits == 0:
                exact = False
            exponent += -e if exp_negative else e
            i = j
        ends = i >= n or buf[i] == 10 or _is_space(buf[i])
        if exact and ends and digits > 0 and mantissa <= _MAX_EXACT and -22 <= exponent <= 22:
            value = float(mantissa)
            value = value * pow10[exponent] if exponent >= 0 else value / pow10[-exponent]
            values[tok] = -value if negative else value
        else:
            while i < n and buf[i] != 10 and not _is_space(buf[i]):
                i += 1
            values[tok] = np.nan
            if n_slow < slow.shape[0]:
                slow[n_slow, 0] = tok
                slow[n_slow, 1] = start
                slow[n_slow, 2] = i
            n_slow += 1
        counts[row] += 1
        tok += 1
    return n_slow


def parse_numbers(data: bytes | np.ndarray) -> Numbers:
    """Every whitespace-separated number of a text, with its line structure.

    Parameters
    ----------
    data : bytes or ndarray of uint8
        The text (ASCII).

    Returns
    -------
    Numbers
        The values and, per non-blank line, how many there are and the line's number.

    Raises
    ------
    ValueError
        ``"line L: 'token' is not a number"`` for the first token that is none.
    """
    buf = np.frombuffer(data, dtype=np.uint8) if isinstance(data, bytes) else data
    n_tokens, n_lines = _count(buf)
    values = np.empty(n_tokens, dtype=np.float64)
    counts = np.empty(n_lines, dtype=np.int64)
    lines = np.empty(n_lines, dtype=np.int64)
    slow = np.empty((min(n_tokens, 4096), 3), dtype=np.int64)
    n_slow = _fill(buf, _POW10, values, counts, lines, slow)
    if n_slow > slow.shape[0]:  # many slow tokens (numbers of 17 digits): list them all
        slow = np.empty((n_slow, 3), dtype=np.int64)
        _fill(buf, _POW10, values, counts, lines, slow)
    if n_slow:
        _parse_slow(buf, slow[:n_slow], values, counts, lines)
    return Numbers(values, counts, lines)


def _parse_slow(
    buf: np.ndarray, slow: np.ndarray, values: np.ndarray, counts: np.ndarray, lines: np.ndarray
) -> None:
    """Parse the tokens listed in ``slow`` (rows ``token, start, stop``) with Python's
    ``float`` (Fortran's ``D`` exponent read as ``E``), in place; a token that is no number is
    an error naming its line."""
    for token, start, stop in slow:
        text = bytes(buf[start:stop]).decode("ascii", errors="replace")
        try:
            values[token] = float(text.replace("D", "E").replace("d", "e"))
        except ValueError:
            row = int(np.searchsorted(np.cumsum(counts), token, side="right"))
            raise ValueError(f"line {int(lines[row])}: {text!r} is not a number") from None
