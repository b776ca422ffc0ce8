"""Configuration files read as data, never as code: the campaign file and the
workflow's config files are refused before they are used when they are not
plain YAML data (a yte template, an alias, a key given twice).

YAML's own loaders keep the last of two equal keys and expand aliases
without bound (an "alias bomb" expands a dozen lines into billions of
values), and Snakemake evaluates a config that sets ``__use_yte__`` as
a template (Python); :func:`check_config_text` reads the raw text without
evaluating or expanding anything, :func:`load_strict` then reads the data.
"""

from __future__ import annotations

import os

import yaml

#: A config is a page of settings: larger files are refused before the file
#: is read as data. So is any YAML alias (``*name``): a value is written
#: where it is used, so that each key reads as it is and no alias bomb can
#: be expanded.
MAX_CONFIG_BYTES = 1_000_000
#: PyYAML's safe loader, its C (libyaml) build where installed (the wheels
#: carry it): the same documents, read several times faster. Every job of the
#: workflow reads its config files again.
SafeLoader = getattr(yaml, "CSafeLoader", yaml.SafeLoader)
#: Keys of yte, the template engine Snakemake runs over a config that sets
#: ``__use_yte__: true``: a config is data, never code.
YTE_KEYS = ("__use_yte__", "__definitions__", "__variables__")


class _StrictLoader(SafeLoader):
    """YAML loader that refuses a key given twice in one mapping (the default
    loaders silently keep the last)."""


def _construct_mapping(loader, node, deep=False):
    seen = {}
    for key_node, _ in node.value:
        key = loader.construct_object(key_node, deep=deep)
        if key in seen:
            raise ValueError(f"key {key!r} given twice in one mapping (lines {seen[key] + 1} and "
                             f"{key_node.start_mark.line + 1}); YAML would silently keep the last")
        seen[key] = key_node.start_mark.line
    return SafeLoader.construct_mapping(loader, node, deep=deep)


_StrictLoader.add_constructor(yaml.resolver.BaseResolver.DEFAULT_MAPPING_TAG, _construct_mapping)


def config_text(path, raw: bytes) -> str:
    """The text of the config file ``path`` (its bytes ``raw``): UTF-8, the
    encoding YAML files are read in here.

    Raises
    ------
    ValueError
        Naming the file, what it holds instead (UTF-16, binary, another
        encoding: the first byte that is not UTF-8) and how to fix it.
    """
    if raw.startswith((b"\xff\xfe", b"\xfe\xff")):
        raise ValueError(f"config file {path}: UTF-16 text (it starts with a UTF-16 byte order mark); "
                         "a config is read as UTF-8: save it as UTF-8")
    nul = raw.find(b"\x00")
    if nul >= 0:
        raise ValueError(f"config file {path}: binary data (a NUL byte at position {nul}), not a YAML text file")
    try:
        return raw.decode("utf-8")
    except UnicodeDecodeError as exc:
        raise ValueError(f"config file {path}: not UTF-8 text (byte 0x{raw[exc.start]:02x} at position "
                         f"{exc.start}: Latin-1 or another encoding?); save it as UTF-8") from None


def load_strict(path) -> dict:
    """Read one YAML config file, refusing duplicate keys.

    Raises
    ------
    ValueError
        Naming the file, the key and both lines; or the file is not UTF-8
        text (:func:`config_text`).
    """
    with open(path, "rb") as fh:
        text = config_text(path, fh.read())
    try:
        return yaml.load(text, Loader=_StrictLoader) or {}
    except ValueError as exc:
        raise ValueError(f"config file {path}: {exc}") from None
    except yaml.YAMLError as exc:
        raise ValueError(f"config file {path}: not plain YAML data: {exc}") from None


def check_config_text(path) -> None:
    """Refuse a config file that is not plain data, reading its raw text
    (nothing evaluated, no alias expanded): larger than
    :data:`MAX_CONFIG_BYTES`, holding a YAML alias (``*name``), a yte key
    (``__use_yte__``, ...) or a string starting with ``?`` (which yte, the
    template engine Snakemake applies to a config setting ``__use_yte__:
    true``, would evaluate as Python).

    Raises
    ------
    ValueError
        Naming the file and the key, or the line of the first alias.
    """
    size = os.stat(path).st_size
    if size > MAX_CONFIG_BYTES:
        raise ValueError(f"config file {path}: {size} bytes, more than the {MAX_CONFIG_BYTES} a config may have")
    with open(path, "rb") as fh:
        text = config_text(path, fh.read())
    try:
        alias = next((e for e in yaml.parse(text, Loader=SafeLoader) if isinstance(e, yaml.AliasEvent)), None)
        if alias is not None:
            raise ValueError(f"line {alias.start_mark.line + 1}: YAML alias *{alias.anchor}: a config is plain "
                             "data, aliases are refused: write the value out where it is used")
        root = yaml.compose(text, Loader=SafeLoader)
    except yaml.YAMLError as exc:
        raise ValueError(f"config file {path}: not valid YAML: {exc}") from None
    except ValueError as exc:
        raise ValueError(f"config file {path}: {exc}") from None
    if root is None:
        return
    stack = [(root, "")]  # a tree (no alias): each node once
    while stack:
        node, key = stack.pop()
        if isinstance(node, yaml.ScalarNode):
            text_value = str(node.value)
            if text_value in YTE_KEYS or text_value.startswith("?"):
                where = key or "(top level)"
                raise ValueError(f"config file {path}: {where}: {text_value!r} is a yte template expression; "
                                 "a config is data, never evaluated: write plain values (and no __use_yte__)")
        elif isinstance(node, yaml.MappingNode):
            for k, v in node.value:
                label = k.value if isinstance(k, yaml.ScalarNode) else "?"
                name = f"{key}.{label}" if key else str(label)
                stack += [(k, name), (v, name)]
        elif isinstance(node, yaml.SequenceNode):
            stack += [(v, f"{key}[{i}]") for i, v in enumerate(node.value)]
