"""The options of an identification, in one place.

:class:`IdentifyOptions` holds every option of ``modal identify``: what the
command line offers, what a campaign file's ``identify`` section and a
workflow config's ``measured`` entry hold, and what a roving setup is
identified with. Each field carries its own description, bounds, command-line
flag and an example value in its metadata, so the argparse options
(:func:`modal.cli.parser`), the JSON schemas of the campaign file and of the
workflow config, and the docs' option table are derived from, or checked
against, this class, and a new option is one field (plus its test).
"""

from __future__ import annotations

import dataclasses
import math
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field

EXCITATIONS = ("ambient", "free_decay")
#: What a channel may measure (:func:`modal.stabilisation`'s ``quantities``).
QUANTITY_NAMES = ("displacement", "velocity", "acceleration")
#: Largest model order when none is given.
MAX_ORDER = 60


def _option(default, help, schema, example, flag=None, metavar=None, choices=None):
    """A field of :class:`IdentifyOptions` with what the command line, the
    schemas and the docs need to know about it (``choices``: the help of each
    value of an option that the command line gives as one flag per value)."""
    metadata = {"help": help, "schema": schema, "example": example, "flag": flag, "metavar": metavar,
                "choices": choices}
    if default is dataclasses.MISSING:
        return field(metadata=metadata)
    return field(default=default, metadata=metadata)


_CHANNEL_LIST = {"type": ["array", "null"], "items": {"type": "integer", "minimum": 0}, "minItems": 1,
                 "uniqueItems": True}


@dataclass(frozen=True)
class IdentifyOptions:
    """Every option of an identification (``modal identify``,
    :func:`modal.identify_record`), checked once, here.

    Build it from keywords, from a mapping (:meth:`from_mapping`: a campaign
    file's ``identify`` section, a workflow config's ``measured`` entry) or
    from the command line; the checks that need the record (fmax below its
    Nyquist frequency, channels it has) are :meth:`record_problems`.

    Attributes
    ----------
    excitation : {"ambient", "free_decay"}
        Output-only (operational) record: NExT correlations; or an impact
        test: the decay after the impact.
    fs : float, optional
        Sampling rate (Hz) overriding the record's own (needed for ``.npy``).
    channels : tuple of int, optional
        The record's channels used, 0-based; default all.
    refs : tuple of int, optional
        Reference channels of the correlations, numbered as the record's
        channels and among ``channels``; default every channel used.
    quantities : tuple of str, optional
        What each channel used measures (``"displacement"``, ``"velocity"``,
        ``"acceleration"``), so mixed channels give one shape; default all
        alike.
    fmax : float, optional
        Highest frequency of interest (Hz): the record is decimated to about
        ``2.5 fmax`` and modes are selected below it; default from the
        record's lowest spectral peak.
    max_order : int
        Largest model order, even.
    rows : int, optional
        Block rows of the Hankel matrix; default from the record (three
        periods of its lowest spectral peak) or, with ``fmax``, 60 or
        ``2 max_order / channels`` if more.
    highpass_hz : float, optional
        Zero-phase high-pass (Hz) before identification, below ``fmax``.
    """

    excitation: str = _option(
        dataclasses.MISSING, "output-only (operational) record, or an impact test (the decay after the impact)",
        {"enum": list(EXCITATIONS)}, "free_decay",
        choices={"ambient": "output-only (operational) record: NExT correlations of the response",
                 "free_decay": "impact test: the decay after the impact (found automatically)"})
    fs: float | None = _option(
        None, "sampling rate (Hz); overrides the record's own rate or time column (needed for .npy)",
        {"type": ["number", "null"], "exclusiveMinimum": 0}, 50.0, "--fs", "HZ")
    channels: tuple[int, ...] | None = _option(
        None, "channels to use, 0-based, e.g. 0,1,2 (default all)", _CHANNEL_LIST, (0, 1), "--channels", "i,j,...")
    refs: tuple[int, ...] | None = _option(
        None, "reference channels of the correlations: the record's channel numbers, among the channels used "
              "(default all used)", _CHANNEL_LIST, (1,), "--refs", "i,j,...")
    quantities: tuple[str, ...] | None = _option(
        None, "what each channel used measures: displacement, velocity or acceleration (d, v, a on the command "
              "line), so mixed channels give one shape (default all alike)",
        {"type": ["array", "null"], "items": {"enum": list(QUANTITY_NAMES)}, "minItems": 1},
        ("velocity", "acceleration"), "--quantities", "q,q,...")
    fmax: float | None = _option(
        None, "highest frequency of interest (Hz); decimates to about 2.5 fmax and selects modes below it "
              "(default: from the record's lowest spectral peak)",
        {"type": ["number", "null"], "exclusiveMinimum": 0}, 5.0, "--fmax", "HZ")
    max_order: int = _option(
        MAX_ORDER, f"largest model order, even (default {MAX_ORDER})",
        {"type": "integer", "minimum": 2, "multipleOf": 2}, 40, "--max-order", "N")
    rows: int | None = _option(
        None, "block rows of the Hankel matrix (default: one period of the record's lowest spectral peak "
              "without fmax, at least 2 max_order / channels; three and at least 60 for a free decay; "
              "60, or 2 max_order / channels if more, with fmax)",
        {"type": ["integer", "null"], "minimum": 1}, 80, "--rows", "N")
    highpass_hz: float | None = _option(
        None, "zero-phase high-pass before identification (Hz), below fmax",
        {"type": ["number", "null"], "exclusiveMinimum": 0}, 0.5, "--highpass", "HZ")

    def __post_init__(self):
        if self.excitation not in EXCITATIONS:
            raise ValueError(f"excitation must be one of {', '.join(EXCITATIONS)}, got {self.excitation!r}")
        for name in ("fs", "fmax", "highpass_hz"):
            value = getattr(self, name)
            if value is not None:
                object.__setattr__(self, name, _positive_number(name, value))
        for name in ("channels", "refs"):
            value = getattr(self, name)
            if value is not None:
                object.__setattr__(self, name, _channel_numbers(name, value))
        if self.quantities is not None:
            object.__setattr__(self, "quantities", _quantities(self.quantities))
        object.__setattr__(self, "max_order", _integer("max_order", self.max_order, minimum=2))
        if self.max_order % 2:
            raise ValueError(f"max_order must be even (each mode is a pair of poles), got {self.max_order}")
        if self.rows is not None:
            object.__setattr__(self, "rows", _integer("rows", self.rows, minimum=1))
        if self.refs is not None and self.channels is not None:
            missing = [r for r in self.refs if r not in self.channels]
            if missing:
                raise ValueError(f"refs {list(missing)} are not among the channels used {list(self.channels)} "
                                 "(refs are the record's channel numbers, like channels)")
        if self.quantities is not None and self.channels is not None and len(self.quantities) != len(self.channels):
            raise ValueError(f"quantities names {len(self.quantities)} channels but channels uses "
                             f"{len(self.channels)}: give one quantity per channel used")
        if self.fmax is not None and self.highpass_hz is not None and self.highpass_hz >= self.fmax:
            raise ValueError(f"highpass_hz = {self.highpass_hz:g} Hz must be below fmax = {self.fmax:g} Hz")
        if self.fs is not None:
            problems = self._rate_problems(self.fs)
            if problems:
                raise ValueError(problems[0])

    @classmethod
    def names(cls) -> tuple[str, ...]:
        """The options' names, in order."""
        return tuple(f.name for f in dataclasses.fields(cls))

    @classmethod
    def from_mapping(cls, mapping: Mapping, where: str = "", other: Sequence[str] = ()) -> IdentifyOptions:
        """The options a mapping gives (missing or ``None``: the default).

        Parameters
        ----------
        mapping : mapping
            Option names to values, e.g. a campaign file's ``identify``
            section or a workflow config's ``measured`` entry.
        where : str
            How messages name the mapping (``"campaign.yaml: identify"``).
        other : sequence of str
            Keys of ``mapping`` that are not options and are left alone
            (``path``, ``setups``, ...); any other unknown key is refused.

        Raises
        ------
        ValueError
            An unknown key, or a value the option does not take; the
            message names the key.
        """
        prefix = f"{where}." if where else ""
        unknown = sorted(set(mapping) - set(cls.names()) - set(other))
        if unknown:
            raise ValueError(f"{prefix}{unknown[0]}: not an option of an identification "
                             f"(options: {', '.join(cls.names())})")
        given = {k: v for k, v in mapping.items() if k in cls.names() and v is not None}
        if "excitation" not in given:
            raise ValueError(f"{prefix}excitation: required ({' or '.join(EXCITATIONS)})")
        try:
            return cls(**given)
        except ValueError as exc:
            raise ValueError(f"{prefix}{exc}") from None

    def to_dict(self) -> dict:
        """The options as plain values (lists, not tuples), every one
        present: what was used, e.g. for ``settings.json``."""
        return {name: list(value) if isinstance(value, tuple) else value
                for name, value in ((n, getattr(self, n)) for n in self.names())}

    def replace(self, **changes) -> IdentifyOptions:
        """A copy with ``changes``, checked like a new one."""
        return dataclasses.replace(self, **changes)

    @classmethod
    def json_schema(cls) -> dict:
        """The JSON schema (``properties`` and ``required``) of a mapping of
        these options, as the campaign file and the workflow config hold it."""
        properties = {}
        for f in dataclasses.fields(cls):
            properties[f.name] = {"description": f.metadata["help"], **f.metadata["schema"]}
        required = [f.name for f in dataclasses.fields(cls) if f.default is dataclasses.MISSING]
        return {"properties": properties, "required": required}

    def _rate_problems(self, fs) -> list[str]:
        nyquist = fs / 2
        return [f"{name} = {getattr(self, name):g} Hz must be below the Nyquist frequency {nyquist:g} Hz "
                f"(fs = {fs:g} Hz)"
                for name in ("fmax", "highpass_hz") if getattr(self, name) is not None
                and getattr(self, name) >= nyquist]

    def record_problems(self, n_channels: int, fs: float, n_samples: int | None = None) -> list[str]:
        """What makes these options impossible on a record of ``n_channels``
        channels sampled at ``fs`` Hz (empty when none): a channel or
        reference the record lacks, a quantity list of another length,
        ``fmax`` or ``highpass_hz`` at or above the Nyquist frequency, and
        with ``n_samples`` (the record's length) rows whose lags it cannot
        hold (:meth:`length_problems`). Each message starts with the
        option's name."""
        problems = []
        for name in ("channels", "refs"):
            beyond = [c for c in getattr(self, name) or () if c >= n_channels]
            if beyond:
                problems.append(f"{name} {beyond}: the record has channels 0 ... {n_channels - 1}")
        used = len(self.channels) if self.channels is not None else n_channels
        if self.quantities is not None and len(self.quantities) != used:
            problems.append(f"quantities names {len(self.quantities)} channels, the identification uses {used}")
        problems += self._rate_problems(fs)
        if n_samples is not None and not problems:
            problems += self.length_problems(n_samples, 1 / fs, used)
        return problems

    def fixed_rows(self, n_channels: int) -> int | None:
        """The block rows when the options fix them: ``rows``, or with
        ``fmax`` the least ``max(60, 2 max_order / channels)`` of the
        ``n_channels`` used; None when the record chooses them."""
        if self.rows is not None:
            return self.rows
        if self.fmax is None:
            return None
        return least_rows(self.max_order, n_channels)

    def decimation(self, dt: float) -> int:
        """The decimation factor ``floor(1 / (2.5 fmax dt))`` of a record
        sampled every ``dt`` s that keeps ``fmax`` inside the anti-aliasing
        filter's pass band (1: none, also without ``fmax``)."""
        factor = 1 if self.fmax is None else int(1 / (dt * 2.5 * self.fmax))
        return factor if factor >= 2 else 1

    def length_problems(self, n_samples: int, dt: float, n_channels: int) -> list[str]:
        """What makes these options impossible on an ambient record of
        ``n_samples`` samples every ``dt`` s, ``n_channels`` of them used:
        its correlations' ``2 rows + 1`` lags must fit in half the record
        as identified (decimated for ``fmax``), which takes ``2 (2 rows +
        1)`` samples. Empty for a free decay and where the record chooses the
        rows (no ``fmax``, no ``rows``). Each message names the option to
        change, with the bound this record allows."""
        rows = self.fixed_rows(n_channels)
        if self.excitation != "ambient" or rows is None:
            return []
        factor, lags = self.decimation(dt), 2 * rows + 1
        kept = n_samples // factor
        if kept >= 2 * lags:
            return []
        most = (kept // 2 - 1) // 2  # the most rows the record as identified takes
        # fewer rows help if they still hold max_order (rows x channels of H(0))
        give = " or ".join(([f"rows = {most} at the most"] if most * n_channels >= self.max_order else [])
                           + ["a longer record"])
        if factor == 1:
            given = f"rows = {rows}" if self.rows is not None else f"fmax = {self.fmax:g} Hz with {rows} rows"
            return [f"{given} needs {lags} lags, more than half the {n_samples}-sample record: give {give}"]
        most_factor = n_samples // (2 * lags)  # floor(1 / (2.5 fmax dt)) <= most_factor: fmax above this bound
        if most_factor >= 1:
            fix = f"fmax must be above {1 / (2.5 * dt * (most_factor + 1)):.4g} Hz for this record (or give {give})"
        else:
            fix = f"no fmax is enough: give {give}"
        return [f"fmax = {self.fmax:g} Hz decimates the {n_samples}-sample record by {factor} to {kept} samples, "
                f"fewer than the {2 * lags} the identification needs ({rows} rows: {lags} lags): {fix}"]

    def check_record(self, n_channels: int, fs: float) -> None:
        """Raise ``ValueError`` with the first of :meth:`record_problems`."""
        problems = self.record_problems(n_channels, fs)
        if problems:
            raise ValueError(problems[0])

    def channel_choice(self, n_channels: int) -> tuple[list[int], list[int] | None]:
        """The record's channels used (default all) and the references as
        positions among them (``None``: every channel used)."""
        self.check_record(n_channels, math.inf)
        channels = list(range(n_channels)) if self.channels is None else list(self.channels)
        refs = None if self.refs is None else [channels.index(r) for r in self.refs]
        return channels, refs


def least_rows(max_order: int, n_channels: int) -> int:
    """The block rows an identification with ``fmax`` takes at the least:
    60, or ``2 max_order / n_channels`` where more (so that ``H(0)``, of
    ``rows x n_channels`` rows, holds twice the highest order)."""
    return max(60, math.ceil(2 * max_order / n_channels))


def identify_options(options=None, **keywords) -> IdentifyOptions:
    """:class:`IdentifyOptions` from what a caller gave: an
    ``IdentifyOptions`` (with ``keywords`` replacing some of its options), an
    excitation name with the other options as ``keywords``, or a mapping."""
    if isinstance(options, IdentifyOptions):
        return options.replace(**keywords) if keywords else options
    if isinstance(options, Mapping):
        return IdentifyOptions.from_mapping({**options, **keywords})
    if options is None and "excitation" not in keywords:
        raise TypeError("an identification needs options (IdentifyOptions) or an excitation")
    if options is not None:
        keywords["excitation"] = options
    return IdentifyOptions(**{k: v for k, v in keywords.items() if v is not None or k == "excitation"})


def _positive_number(name, value) -> float:
    if isinstance(value, bool) or not isinstance(value, (int, float)):
        raise ValueError(f"{name} must be a positive number, got {value!r}")
    if not (math.isfinite(value) and value > 0):
        raise ValueError(f"{name} must be a positive finite number, got {value!r}")
    return float(value)


def _integer(name, value, minimum) -> int:
    if isinstance(value, bool) or not isinstance(value, int):
        if isinstance(value, (bool, float)) or not hasattr(value, "__index__"):
            raise ValueError(f"{name} must be an integer, got {value!r}")
        value = int(value)
    if value < minimum:
        raise ValueError(f"{name} must be at least {minimum}, got {value}")
    return int(value)


def _channel_numbers(name, values) -> tuple[int, ...]:
    if isinstance(values, (str, bytes)) or not isinstance(values, Sequence) and not hasattr(values, "__iter__"):
        raise ValueError(f"{name} must be a list of channel numbers, got {values!r}")
    numbers = tuple(_integer(f"{name} entry", v, minimum=0) for v in values)
    if not numbers:
        raise ValueError(f"{name} must name at least one channel (or be left out for all)")
    if len(set(numbers)) != len(numbers):
        raise ValueError(f"{name} {list(numbers)} names a channel twice")
    return numbers


def _quantities(values) -> tuple[str, ...]:
    if isinstance(values, str):
        raise ValueError(f"quantities must be a list, one of {', '.join(QUANTITY_NAMES)} per channel, got {values!r}")
    values = tuple(values)
    bad = [v for v in values if v not in QUANTITY_NAMES]
    if bad or not values:
        raise ValueError(f"quantities must name one of {', '.join(QUANTITY_NAMES)} for each channel used, "
                         f"got {list(values)}")
    return values
