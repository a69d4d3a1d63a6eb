"""The one number check: a value against a range, for creature files, ``--path`` and
``--terrain`` texts, scene files, command-line options and clip limits.

A leaf module. :class:`Range` says what is allowed (open or closed bounds, a unit,
whole numbers only); :meth:`Range.check` returns the number or raises
:class:`NumberProblem` whose text callers put after their own "where" (a file and key,
an option): ``expected a number in (0, 20] (Hz)`` or ``must be <= 80 deg``.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Literal

Phrasing = Literal["expected", "bound"]


class NumberProblem(ValueError):
    """A value that is not a number, not finite, not whole or out of its range; the
    message says what is allowed."""


@dataclass(frozen=True)
class Range:
    """Allowed numbers: ``lo``..``hi`` (either may be None), each bound open or closed;
    ``unit`` for messages; ``integer`` for whole numbers."""

    lo: float | None = None
    hi: float | None = None
    lo_open: bool = False
    hi_open: bool = False
    unit: str = ""
    integer: bool = False

    def allowed(self) -> str:
        """What is allowed, as a phrase: ``a number in (0, 20] (Hz)``, ``a whole number >= 1``."""
        what = "a whole number" if self.integer else "a number"
        lo = None if self.lo is None else f"{'>' if self.lo_open else '>='} {self.lo:g}"
        hi = None if self.hi is None else f"{'<' if self.hi_open else '<='} {self.hi:g}"
        bounds = " and ".join(b for b in (lo, hi) if b)
        if self.lo is not None and self.hi is not None:
            bounds = f"in {'(' if self.lo_open else '['}{self.lo:g}, {self.hi:g}{')' if self.hi_open else ']'}"
        return f"{what} {bounds}".strip() + (f" ({self.unit})" if self.unit else "")

    def broken_bound(self, number: float) -> str | None:
        """The first bound ``number`` breaks, as ``must be >= 0 m``; None inside the range."""
        unit = f" {self.unit}" if self.unit else ""
        if self.lo is not None and (number < self.lo or (self.lo_open and number == self.lo)):
            return f"must be {'>' if self.lo_open else '>='} {self.lo:g}{unit}"
        if self.hi is not None and (number > self.hi or (self.hi_open and number == self.hi)):
            return f"must be {'<' if self.hi_open else '<='} {self.hi:g}{unit}"
        return None

    def check(self, value: object, phrasing: Phrasing = "expected") -> float:
        """``value`` (a number, or text to read as one) as a float (an int for whole
        numbers), or :class:`NumberProblem`: "expected ..." (what :meth:`allowed` says) or,
        with ``phrasing="bound"``, the broken bound ("must be <= 80 deg")."""
        number = to_number(value, self.allowed())
        if self.integer:
            try:
                whole = float(number) == int(number)
            except OverflowError:
                whole = False
            if not whole:
                raise NumberProblem(f"expected {self.allowed()}" if phrasing == "expected" else "must be a whole number")
            number = int(number)
        broken = self.broken_bound(number)
        if broken is not None:
            raise NumberProblem(f"expected {self.allowed()}" if phrasing == "expected" else broken)
        return number if self.integer else float(number)


def to_number(value: object, allowed: str = "a number") -> float:
    """A finite number from a number or its text; :class:`NumberProblem` otherwise
    (booleans are not numbers)."""
    if isinstance(value, str):
        try:
            value = float(value)
        except ValueError:
            raise NumberProblem("is not a number") from None
    if isinstance(value, bool) or not isinstance(value, (int, float)):
        raise NumberProblem(f"expected {allowed}")
    try:
        number = float(value)
    except OverflowError:  # an integer too large for a float
        raise NumberProblem(f"expected {allowed}") from None
    if not math.isfinite(number):
        raise NumberProblem(f"not a finite number; expected {allowed}")
    return int(value) if isinstance(value, int) and not isinstance(value, bool) else number
