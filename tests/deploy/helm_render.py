#!/usr/bin/python3
"""Renders a Helm chart's templates with the subset of Go templating that
deploy/helm/gistream uses, so the chart can be checked without helm (not
packaged in Debian 12). Anything outside the subset is an error, so a
template that grows past it fails the test instead of rendering wrongly.

Subset: {{ }} and {{- -}} (whitespace trimming); if / else / end; range /
end (over a list, "." the element); pipelines of .Values.a.b, .Release.Name,
".", integer and string literals, parenthesised calls; functions quote,
toYaml, nindent N, int, add A B, gt A B.

    helm_render.py CHART [--release NAME] [--set-json JSON]   (prints every template)
"""

import argparse
import copy
import json
import os
import re
import sys

import yaml

_ACTION = re.compile(r"\{\{(-?)\s*(.*?)\s*(-?)\}\}", re.S)


class TemplateError(Exception):
    pass


def _tokens(text):
    """Text and action tokens, with {{- / -}} trimming applied."""
    out, pos = [], 0
    for m in _ACTION.finditer(text):
        chunk = text[pos:m.start()]
        if m.group(1):
            chunk = chunk.rstrip()
        out.append(("text", chunk))
        out.append(("action", m.group(2)))
        pos = m.end()
        if m.group(3):
            rest = text[pos:]
            pos += len(rest) - len(rest.lstrip())
    out.append(("text", text[pos:]))
    return out


def _parse(tokens):
    """A tree of ("text", s), ("expr", e), ("if", e, then, else), ("range", e, body)."""
    def block(i, stop):
        nodes = []
        while i < len(tokens):
            kind, value = tokens[i]
            if kind == "text":
                nodes.append(("text", value))
                i += 1
                continue
            word = value.split(None, 1)[0] if value else ""
            if word in stop:
                return nodes, i
            if word == "if":
                then, i = block(i + 1, ("else", "end"))
                other = []
                if tokens[i][1] == "else":
                    other, i = block(i + 1, ("end",))
                nodes.append(("if", value[2:].strip(), then, other))
                i += 1
            elif word == "range":
                body, i = block(i + 1, ("end",))
                nodes.append(("range", value[5:].strip(), body))
                i += 1
            elif word in ("else", "end", "with", "define", "template", "include", "block"):
                raise TemplateError(f"unsupported or misplaced action {{{{ {value} }}}}")
            else:
                nodes.append(("expr", value))
                i += 1
        if stop:
            raise TemplateError(f"missing {{{{ end }}}} (expected one of {stop})")
        return nodes, i
    nodes, _ = block(0, ())
    return nodes


def _split_args(expr):
    """Top-level words of a call, keeping parenthesised groups and strings."""
    words, depth, cur, quoted = [], 0, "", False
    for ch in expr:
        if ch == '"':
            quoted = not quoted
        if not quoted and ch == "(":
            depth += 1
        elif not quoted and ch == ")":
            depth -= 1
        if not quoted and depth == 0 and ch.isspace():
            if cur:
                words.append(cur)
            cur = ""
        else:
            cur += ch
    if cur:
        words.append(cur)
    return words


def _to_yaml(value):
    # Keys sorted, as helm's toYaml does.
    return yaml.safe_dump(value, default_flow_style=False, sort_keys=True).rstrip("\n")


_FUNCTIONS = {
    "quote": lambda v: json.dumps(str(v)),
    "toYaml": _to_yaml,
    "nindent": lambda n, v: "\n" + "\n".join(" " * int(n) + line for line in str(v).split("\n")),
    "int": lambda v: int(v),
    "add": lambda a, b: int(a) + int(b),
    "gt": lambda a, b: a > b,
}


def _truthy(v):
    return bool(v) if not isinstance(v, (int, float)) or isinstance(v, bool) else v != 0


class _Renderer:
    def __init__(self, values, release):
        self.root = {"Values": values, "Release": {"Name": release}}

    def term(self, word, dot):
        if word.startswith("(") and word.endswith(")"):
            return self.pipeline(word[1:-1], dot)
        if word == ".":
            return dot
        if word.startswith("."):
            value = self.root
            for key in word[1:].split("."):
                if not isinstance(value, dict) or key not in value:
                    raise TemplateError(f"{word}: no such value")
                value = value[key]
            return value
        if re.fullmatch(r"-?\d+", word):
            return int(word)
        if word.startswith('"') and word.endswith('"'):
            return json.loads(word)
        raise TemplateError(f"unsupported term {word!r}")

    def call(self, expr, dot, piped=None):
        words = _split_args(expr)
        if words[0] in _FUNCTIONS:
            args = [self.term(w, dot) for w in words[1:]]
            if piped is not None:
                args.append(piped[0])
            return _FUNCTIONS[words[0]](*args)
        if len(words) != 1 or piped is not None:
            raise TemplateError(f"unsupported call {expr!r}")
        return self.term(words[0], dot)

    def pipeline(self, expr, dot):
        stages = [s.strip() for s in expr.split("|")]
        value = self.call(stages[0], dot)
        for stage in stages[1:]:
            value = self.call(stage, dot, piped=(value,))
        return value

    def render(self, nodes, dot=None):
        out = []
        for node in nodes:
            kind = node[0]
            if kind == "text":
                out.append(node[1])
            elif kind == "expr":
                value = self.pipeline(node[1], dot)
                out.append("" if value is None else (str(value).lower() if isinstance(value, bool)
                                                     else str(value)))
            elif kind == "if":
                branch = node[2] if _truthy(self.pipeline(node[1], dot)) else node[3]
                out.append(self.render(branch, dot))
            elif kind == "range":
                items = self.pipeline(node[1], dot) or []
                if not isinstance(items, list):
                    raise TemplateError(f"range over {type(items).__name__}: lists only")
                out.extend(self.render(node[2], item) for item in items)
        return "".join(out)


def merge(base, override):
    """`override` deep-merged into a copy of `base` (as helm --set does)."""
    out = copy.deepcopy(base)
    for key, value in override.items():
        if isinstance(value, dict) and isinstance(out.get(key), dict):
            out[key] = merge(out[key], value)
        else:
            out[key] = copy.deepcopy(value)
    return out


def render_chart(chart, release="gistream", overrides=None):
    """{template file name: rendered text}, with the chart's values.yaml
    merged with `overrides`."""
    with open(os.path.join(chart, "values.yaml")) as f:
        values = merge(yaml.safe_load(f) or {}, overrides or {})
    renderer = _Renderer(values, release)
    out = {}
    folder = os.path.join(chart, "templates")
    for name in sorted(os.listdir(folder)):
        if not name.endswith(".yaml"):
            continue
        with open(os.path.join(folder, name)) as f:
            try:
                out[name] = renderer.render(_parse(_tokens(f.read())))
            except TemplateError as e:
                raise TemplateError(f"{name}: {e}") from None
    return out


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("chart")
    parser.add_argument("--release", default="gistream")
    parser.add_argument("--set-json", default="{}", help="values to merge, as JSON")
    args = parser.parse_args()
    for name, text in render_chart(args.chart, args.release, json.loads(args.set_json)).items():
        if text.strip():
            sys.stdout.write(f"---\n# Source: {os.path.basename(args.chart)}/templates/{name}\n")
            sys.stdout.write(text.strip("\n") + "\n")


if __name__ == "__main__":
    main()
