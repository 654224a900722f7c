"""Minimal reader for the namelist text MPMICE echoes (``<name>.used.nml`` and the ``namelist``
attribute of dumps and checkpoints).

Only what the program writes is supported: ``&group name = value, ... /`` with scalars, arrays,
quoted strings and logicals. Returns ``{group: {variable: value}}`` with lower-case keys; arrays
are lists. Repeated groups (``&fluid``, ``&solid``, ``&region``, ``&boundary``) appear once per
occurrence in the text: ``parse_namelist_groups`` returns every group in order, while
``parse_namelist_text`` keeps the last occurrence of each.
"""
from __future__ import annotations

import re

_TOKEN = re.compile(r"""'(?:[^']|'')*'|"(?:[^"]|"")*"|[^\s,]+""")


def _convert(token: str):
    if token[0] in "'\"":
        return token[1:-1].replace(token[0] * 2, token[0])
    low = token.lower()
    if low in (".true.", "t", ".t.", "true"):
        return True
    if low in (".false.", "f", ".f.", "false"):
        return False
    if "*" in token:  # repeat count r*value
        count, value = token.split("*", 1)
        return [_convert(value)] * int(count)
    try:
        return int(token)
    except ValueError:
        return float(low.replace("d", "e"))


def _strip_comments(text: str) -> str:
    """``text`` without its ``!`` comments (a ``!`` inside a quoted string is kept): the echo
    writes unset variables as comment lines (``! solid_velocity_times = unset``)."""
    lines = []
    for line in text.splitlines():
        quote = None
        for i, c in enumerate(line):
            if quote:
                if c == quote:
                    quote = None
            elif c in "'\"":
                quote = c
            elif c == "!":
                line = line[:i]
                break
        lines.append(line)
    return "\n".join(lines) + "\n"


def parse_namelist_text(text: str) -> dict[str, dict[str, object]]:
    """Parse namelist text into nested dictionaries (the last occurrence of a repeated group)."""
    return dict(parse_namelist_groups(text))


def parse_namelist_groups(text: str) -> list[tuple[str, dict[str, object]]]:
    """Parse namelist text into ``(group, {variable: value})`` pairs, one per group, in order."""
    groups: list[tuple[str, dict[str, object]]] = []
    text = _strip_comments(text)
    for match in re.finditer(r"&(\w+)(.*?)(?:^\s*/\s*$|/\s*$|/\s*\n)", text, re.S | re.M):
        group = match.group(1).lower()
        body = match.group(2)
        values: dict[str, object] = {}
        # split into "name = values" assignments
        parts = re.split(r"(?:^|[\s,])([A-Za-z_]\w*(?:\(\s*\d+\s*\))?)\s*=", body)
        for name, raw in zip(parts[1::2], parts[2::2]):
            tokens = [_convert(t) for t in _TOKEN.findall(raw)]
            flat: list[object] = []
            for t in tokens:
                flat.extend(t if isinstance(t, list) else [t])
            key = re.sub(r"\(.*", "", name).lower()
            values[key] = flat[0] if len(flat) == 1 else flat
        groups.append((group, values))
    return groups


def read_namelist_file(path: str) -> dict[str, dict[str, object]]:
    """Parse a namelist file."""
    with open(path, encoding="utf-8") as handle:
        return parse_namelist_text(handle.read())
