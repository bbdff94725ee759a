#!/usr/bin/python3
"""No function of the product's code is longer than 80 lines (issue 28).

Scans server/, client/, common/ and web/ (.cpp and .h; tests are not held
to it): comments and string literals are blanked, then every brace that
opens at namespace or class scope after a parenthesised header (not a
namespace, class, struct, enum or initialiser) opens a function body,
measured from the header's first line to its closing brace. Lambdas and
blocks inside a body count towards it. Prints each function over the
limit with its file and line and exits 1 when there is one.

usage: function_length.py [ROOT] [--limit N] [--list N]
"""
import re
import sys
from pathlib import Path

LIMIT = 80
DIRS = ("server", "client", "common", "web")
SCOPE_WORDS = re.compile(r"\b(namespace|class|struct|union|enum)\b")
CONTROL = re.compile(r"^\s*(if|for|while|switch|catch|do|else|try)\b")


def blank(src: str) -> str:
    """Comments and literals replaced by spaces, newlines kept."""
    out = []
    i, n = 0, len(src)
    while i < n:
        c = src[i]
        if src.startswith("//", i):
            j = src.find("\n", i)
            j = n if j < 0 else j
            out.append(" " * (j - i))
            i = j
        elif src.startswith("/*", i):
            j = src.find("*/", i + 2)
            j = n if j < 0 else j + 2
            out.append(re.sub(r"[^\n]", " ", src[i:j]))
            i = j
        elif c == "R" and src.startswith('R"', i) and (i == 0 or not (src[i - 1].isalnum() or src[i - 1] == "_")):
            k = src.find("(", i + 2)
            delim = src[i + 2:k]
            j = src.find(")" + delim + '"', k)
            j = n if j < 0 else j + len(delim) + 2
            out.append(re.sub(r"[^\n]", " ", src[i:j]))
            i = j
        elif c in "\"'":
            if c == "'" and i > 0 and src[i - 1].isalnum():  # digit separator 1'000
                out.append(" ")
                i += 1
                continue
            j = i + 1
            while j < n and src[j] != c:
                j += 2 if src[j] == "\\" else 1
            out.append(re.sub(r"[^\n]", " ", src[i:j + 1]))
            i = j + 1
        else:
            out.append(c)
            i += 1
    return "".join(out)


def functions(text: str):
    """(first line, last line, header) of each function body."""
    stack = []  # "scope" | "fn" | "other"
    header_start = 0
    fn_start = []
    for i, c in enumerate(text):
        if c == "{":
            inside_fn = "fn" in stack
            header = text[header_start:i]
            kind = "other"
            if not inside_fn:
                stripped = header.strip()
                if SCOPE_WORDS.search(stripped.split("(")[0]) or stripped.startswith("extern"):
                    kind = "scope"
                elif ("(" in stripped and ")" in stripped and not stripped.endswith("=")
                      and not CONTROL.match(stripped) and "=" not in stripped.split("(")[0]):
                    kind = "fn"
                    first = header_start + (len(header) - len(header.lstrip()))
                    fn_start.append((text.count("\n", 0, first) + 1, stripped.splitlines()[0]))
            stack.append(kind)
            header_start = i + 1
        elif c == "}":
            if stack:
                kind = stack.pop()
                if kind == "fn":
                    line, head = fn_start.pop()
                    yield line, text.count("\n", 0, i) + 1, head
            header_start = i + 1
        elif c == ";" or (c == ":" and text.startswith(("public:", "private:", "protected:"), max(0, i - 9))):
            header_start = i + 1
        elif c == "#" and (i == 0 or text[i - 1] == "\n"):
            header_start = text.find("\n", i) + 1  # a preprocessor line


def main(argv):
    root = Path(argv[1]) if len(argv) > 1 and not argv[1].startswith("--") else Path(__file__).resolve().parents[2]
    limit = int(argv[argv.index("--limit") + 1]) if "--limit" in argv else LIMIT
    listed = int(argv[argv.index("--list") + 1]) if "--list" in argv else 0
    found = []
    for d in DIRS:
        for path in sorted((root / d).rglob("*")):
            if path.suffix not in (".cpp", ".h") or not path.is_file():
                continue
            text = blank(path.read_text(errors="replace"))
            for first, last, head in functions(text):
                found.append((last - first + 1, path.relative_to(root), first, head))
    found.sort(reverse=True)
    for n, path, line, head in found[:listed]:
        print(f"{n:5d}  {path}:{line}  {head[:80]}")
    over = [f for f in found if f[0] > limit]
    for n, path, line, head in over:
        print(f"{path}:{line}: {n} lines (limit {limit}): {head[:80]}")
    print(f"{len(found)} functions, {len(over)} over {limit} lines")
    return 1 if over else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
