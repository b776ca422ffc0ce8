"""MkDocs hook: the configuration reference (docs/configuration.md) written
from the schemas at build time, so it cannot fall behind them.

Each marker line of the page becomes a table with one row per key: its
dotted path (``<name>`` stands for a key the user chooses), type, bounds,
whether it is required, its default and its description.

- ``<!-- config-reference: workflow -->``: workflow/schemas/config.schema.yaml;
- ``<!-- config-reference: campaign -->``: a campaign file
  (``modal.campaign._config.SCHEMA``, its defaults from the same module).
"""

from __future__ import annotations

import html
import json
from pathlib import Path

import yaml

ROOT = Path(__file__).resolve().parents[2]
WORKFLOW_SCHEMA = ROOT / "workflow" / "schemas" / "config.schema.yaml"
MARKER = "<!-- config-reference: {} -->"


def _resolve(schema: dict, root: dict) -> dict:
    while "$ref" in schema:
        target = root
        for part in schema["$ref"].removeprefix("#/").split("/"):
            target = target[part]
        schema = {**target, **{k: v for k, v in schema.items() if k != "$ref"}}
    return schema


def _value(value) -> str:
    return f"`{json.dumps(value)}`" if not isinstance(value, str) else f"`{value}`"


def _kind(schema: dict, root: dict) -> str:
    schema = _resolve(schema, root)
    if "enum" in schema:
        return "one of " + ", ".join(_value(v) for v in schema["enum"])
    if "oneOf" in schema and "type" not in schema:
        return " or ".join(_kind(branch, root) for branch in schema["oneOf"])
    types = schema.get("type", "any")
    types = types if isinstance(types, list) else [types]
    words = []
    for kind in (t for t in types if t != "null"):
        if kind == "array" and "items" in schema:
            words.append(f"list of {_kind(schema['items'], root)}")
        elif kind == "object" and isinstance(schema.get("additionalProperties"), dict) \
                and "properties" not in schema:
            words.append("mapping")
        else:
            words.append(kind)
    return " or ".join(words) + (" (or null)" if "null" in types else "")


def _bounds(schema: dict, root: dict) -> str:
    schema = _resolve(schema, root)
    parts = []
    if schema.get("minItems") is not None and schema.get("minItems") == schema.get("maxItems"):
        schema = {**schema, "items_exactly": schema["minItems"]}
        del schema["minItems"], schema["maxItems"]
    for key, text in (("minimum", "≥ {}"), ("exclusiveMinimum", "> {}"), ("maximum", "≤ {}"),
                      ("exclusiveMaximum", "< {}"), ("multipleOf", "multiple of {}"),
                      ("items_exactly", "{} items"), ("minItems", "at least {} items"),
                      ("maxItems", "at most {} items"), ("minLength", "at least {} characters"),
                      ("maxLength", "at most {} characters"), ("minProperties", "at least {} entries")):
        if key in schema:
            non_empty = key in ("minItems", "minLength", "minProperties") and schema[key] == 1
            parts.append("non-empty" if non_empty else text.format(schema[key]))
    if schema.get("uniqueItems"):
        parts.append("no repeats")
    if "pattern" in schema:
        parts.append(f"matches `{schema['pattern']}`")
    names = _resolve(schema.get("propertyNames", {}), root)
    if "pattern" in names:
        parts.append(f"names match `{names['pattern']}`")
    if "enum" in names:
        parts.append("names " + ", ".join(_value(v) for v in names["enum"]))
    items = _resolve(schema["items"], root) if isinstance(schema.get("items"), dict) else {}
    if "items" in schema and "enum" not in items and _bounds(items, root):
        parts.append(f"each {_bounds(items, root).replace('; ', ' and ')}")
    return "; ".join(parts)


def _text(text: str) -> str:
    return html.escape(" ".join(text.split()), quote=False).replace("|", "\\|")


def _rows(schema: dict, root: dict, path: str, required: bool, defaults: dict) -> list[list[str]]:
    schema = _resolve(schema, root)
    description = schema.get("description", "")
    choices = [branch["required"] for branch in schema.get("oneOf", []) if set(branch) <= {"required", "not"}]
    if choices:
        description += (" " if description else "") + "Give one of: " + \
            "; ".join(" with ".join(f"`{k}`" for k in keys) for keys in choices) + "."
    default = schema.get("default", defaults.get(path, ...))
    rows = [[f"`{path}`", _kind(schema, root), _bounds(schema, root), "yes" if required else "",
             "" if default is ... else _value(default), _text(description)]] if path else []
    if "properties" in schema:
        for key, sub in schema["properties"].items():
            rows += _rows(sub, root, f"{path}.{key}" if path else key, key in schema.get("required", []), defaults)
    elif isinstance(schema.get("additionalProperties"), dict):
        rows += _rows(schema["additionalProperties"], root, f"{path}.<name>", False, defaults)
    return rows


def reference_table(schema: dict, defaults: dict | None = None) -> str:
    """A Markdown table of every key of ``schema`` (a JSON schema of a
    mapping); ``defaults`` maps dotted paths to the defaults the code fills
    in (the schema's own ``default`` annotations are taken too)."""
    header = ["key", "type", "bounds", "required", "default", "description"]
    lines = ["| " + " | ".join(header) + " |", "|" + "---|" * len(header)]
    lines += ["| " + " | ".join(row) + " |" for row in _rows(schema, schema, "", True, defaults or {})]
    return "\n".join(lines)


def workflow_reference() -> str:
    return reference_table(yaml.safe_load(WORKFLOW_SCHEMA.read_text()))


def campaign_reference() -> str:
    import dataclasses

    from modal.campaign import _config

    defaults = {f"tracking.{key}": value for key, value in _config.TRACKING_DEFAULTS.items()}
    defaults["chunk"] = _config.CHUNK
    try:  # the identify options' own defaults (one home: modal.IdentifyOptions)
        from modal.measured import IdentifyOptions
    except ImportError:
        pass
    else:
        defaults.update({f"identify.{f.name}": f.default for f in dataclasses.fields(IdentifyOptions)
                         if f.default is not dataclasses.MISSING})
    return reference_table(_config.SCHEMA, defaults)


def on_page_markdown(markdown: str, page, **kwargs) -> str:
    if page.file.src_uri != "configuration.md":
        return markdown
    for name, table in (("workflow", workflow_reference), ("campaign", campaign_reference)):
        markdown = markdown.replace(MARKER.format(name), table())
    return markdown
