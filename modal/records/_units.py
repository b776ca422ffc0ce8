"""The one spelling of a unit that a record or a channel table names."""

from __future__ import annotations

import re
import unicodedata

__all__ = ["unit_key"]


def unit_key(unit) -> str:
    """The one spelling of ``unit`` (the channel tables' unit list uses it): Unicode compatibility
    form (the micro sign and the Greek mu are one letter, superscripts plain
    digits), lower case, ``u`` for micro, without spaces, ``^``, ``*`` or
    ``·``, and a negative power of s written as a division: ``m s^-2``,
    ``m·s⁻²``, ``m/s**2`` and ``m/s²`` are all ``m/s2``; ``µm/s`` is ``um/s``."""
    key = unicodedata.normalize("NFKC", str(unit)).strip().lower().replace("\u03bc", "u").replace("\u2212", "-")
    key = re.sub(r"[\s^*\u00b7\u22c5]", "", key)
    return re.sub(r"s-([12])$", lambda m: "/s" + ("2" if m.group(1) == "2" else ""), key)
