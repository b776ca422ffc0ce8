"""Configuration files read as data, never as code: the campaign file and the
workflow's config files are refused before they are used when they are not
plain YAML data (a yte template, an alias bomb, a key given twice).

YAML's own loaders keep the last of two equal keys and expand aliases
without bound, and Snakemake evaluates a config that sets ``__use_yte__`` as
a template (Python); :func:`check_config_text` reads the raw text without
evaluating or expanding anything, :func:`load_strict` then reads the data.
"""

from __future__ import annotations

import os

import yaml

#: A config is a page of settings: larger files, and YAML aliases beyond these
#: (an alias bomb expands a few lines into billions of nodes), are refused
#: before the file is read as data.
MAX_CONFIG_BYTES = 1_000_000
MAX_ALIASES = 100
MAX_CONFIG_NODES = 100_000
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
    :data:`MAX_CONFIG_BYTES`, more than :data:`MAX_ALIASES` aliases or
    :data:`MAX_CONFIG_NODES` nodes once expanded, a yte key
    (``__use_yte__``, ...) or a string starting with ``?`` (which yte, the
    template engine Snakemake applies to a config setting ``__use_yte__:
    true``, would evaluate as Python).

    Raises
    ------
    ValueError
        Naming the file and the key.
    """
    size = os.stat(path).st_size
    if size > MAX_CONFIG_BYTES:
        raise ValueError(f"config file {path}: {size} bytes, more than the {MAX_CONFIG_BYTES} a config may have")
    with open(path, "rb") as fh:
        text = config_text(path, fh.read())
    try:
        n_aliases = sum(isinstance(e, yaml.AliasEvent) for e in yaml.parse(text, Loader=SafeLoader))
        if n_aliases > MAX_ALIASES:
            raise ValueError(f"{n_aliases} YAML aliases (*name), more than {MAX_ALIASES}: write the values out")
        root = yaml.compose(text, Loader=SafeLoader)
    except yaml.YAMLError as exc:
        raise ValueError(f"config file {path}: not valid YAML: {exc}") from None
    except ValueError as exc:
        raise ValueError(f"config file {path}: {exc}") from None
    if root is None:
        return
    # Each node once (an alias points to a node already seen): linear in the text.
    sizes, seen, stack = {}, set(), [(root, "")]
    while stack:
        node, key = stack.pop()
        if id(node) in seen:
            continue
        seen.add(id(node))
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
    if _expanded_nodes(root, sizes) > MAX_CONFIG_NODES:
        raise ValueError(f"config file {path}: more than {MAX_CONFIG_NODES} values once its aliases are expanded")


def _expanded_nodes(node, sizes) -> int:
    """Nodes of ``node`` with every alias expanded, each shared node counted
    once per use but computed once (``sizes`` memoises; iterative)."""
    stack = [(node, False)]
    while stack:
        current, done = stack.pop()
        if id(current) in sizes:
            continue
        children = ([x for pair in current.value for x in pair] if isinstance(current, yaml.MappingNode)
                    else list(current.value) if isinstance(current, yaml.SequenceNode) else [])
        if done:
            sizes[id(current)] = 1 + sum(sizes[id(c)] for c in children)
        else:
            stack.append((current, True))
            stack += [(c, False) for c in children if id(c) not in sizes]
    return sizes[id(node)]
