#!/usr/bin/env python3
"""Function-length census of the C++ sources.

Finds every function body in the .cpp/.h files under src/ (or the folders given
with --paths) and prints how many there are, how many are over 60 and over 100
lines, and the longest ones with file:line, qualified name and length.

A function's length is the number of lines from the line holding its name to
the line of its closing brace, both included. Lambdas, local classes and
blocks inside a function belong to that function. Comments, string literals
(raw strings too), character literals and preprocessor lines are blanked
before the braces are matched.

usage: function_census.py [--paths DIR ...] [--top N] [--over N]
"""
import argparse
import os
import re
import sys

SOURCE_SUFFIXES = (".cpp", ".h", ".hpp", ".cc")
REPO_DIR = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))


def blank_non_code(text):
    """Returns text of the same length and line layout in which comments,
    string and character literals and preprocessor lines are spaces."""
    out = list(text)
    n = len(text)
    i = 0
    line_start = True  # only white space since the last newline

    def blank(a, b):
        for k in range(a, b):
            if out[k] != "\n":
                out[k] = " "

    while i < n:
        c = text[i]
        if c == "\n":
            line_start = True
            i += 1
            continue
        if c in " \t\r\f\v":
            i += 1
            continue
        if line_start and c == "#":
            j = i
            while j < n and text[j] != "\n":
                if text[j] == "\\" and j + 1 < n and text[j + 1] == "\n":
                    j += 2
                    continue
                if text.startswith("/*", j):
                    end = text.find("*/", j + 2)
                    j = n if end < 0 else end + 2
                    continue
                j += 1
            blank(i, j)
            i = j
            continue
        line_start = False
        if text.startswith("//", i):
            j = text.find("\n", i)
            j = n if j < 0 else j
            blank(i, j)
            i = j
            continue
        if text.startswith("/*", i):
            end = text.find("*/", i + 2)
            j = n if end < 0 else end + 2
            blank(i, j)
            i = j
            continue
        if c == '"':
            m = re.compile(r'(?:u8|[uUL])?R$').search(text, max(0, i - 3), i)
            if m and (m.start() == 0 or not (text[m.start() - 1].isalnum() or text[m.start() - 1] == "_")):
                open_paren = text.find("(", i + 1)
                delim = text[i + 1:open_paren]
                end = text.find(")" + delim + '"', open_paren + 1)
                j = n if end < 0 else end + len(delim) + 2
                blank(i + 1, j - 1)
                i = j
                continue
            j = i + 1
            while j < n and text[j] != '"' and text[j] != "\n":
                j += 2 if text[j] == "\\" else 1
            blank(i + 1, min(j, n))
            i = j + 1
            continue
        if c == "'":
            # A digit separator (1'000'000) follows a number; a character
            # literal follows anything else (u8'x' and L'x' start with a letter).
            k = i
            while k > 0 and (text[k - 1].isalnum() or text[k - 1] in "_.'"):
                k -= 1
            if k < i and text[k].isdigit():
                i += 1
                continue
            j = i + 1
            while j < n and text[j] != "'" and text[j] != "\n":
                j += 2 if text[j] == "\\" else 1
            blank(i + 1, min(j, n))
            i = j + 1
            continue
        i += 1
    return "".join(out)


def match_brace(code, open_pos):
    """Position of the brace closing the one at open_pos (len(code) if none)."""
    depth = 0
    for k in range(open_pos, len(code)):
        ch = code[k]
        if ch == "{":
            depth += 1
        elif ch == "}":
            depth -= 1
            if depth == 0:
                return k
    return len(code)


def strip_template_prefix(header):
    """Removes leading 'template <...>' clauses (angle brackets matched)."""
    while True:
        m = re.match(r"\s*template\s*<", header)
        if not m:
            return header
        depth = 0
        k = m.end() - 1
        while k < len(header):
            if header[k] == "<":
                depth += 1
            elif header[k] == ">":
                depth -= 1
                if depth == 0:
                    break
            k += 1
        header = header[k + 1:]


def top_level(header):
    """The header with parenthesised text replaced by '(...)' markers: returns
    (flattened text, list of (start, end) of top-level paren groups)."""
    groups = []
    depth = 0
    start = 0
    for k, ch in enumerate(header):
        if ch == "(":
            if depth == 0:
                start = k
            depth += 1
        elif ch == ")":
            depth -= 1
            if depth == 0:
                groups.append((start, k))
    return groups


NAME_BEFORE_PAREN = re.compile(
    r"((?:[A-Za-z_]\w*(?:<[^;{}()]*?>)?\s*::\s*)*"
    r"(?:operator\s*(?:\(\s*\)|[^\s(\w]+|\s\w[\w\s:<>*&]*)|~?[A-Za-z_]\w*))\s*$")
NOT_NAMES = {"decltype", "alignas", "__attribute__", "__declspec", "noexcept", "throw",
             "sizeof", "static_assert", "if", "while", "for", "switch", "return"}


def function_name(header):
    """The (possibly qualified) name of the function a header declares, with
    its offset in header, or None when the header is not a function's."""
    for start, _ in top_level(header):
        if header.startswith("()", start) and re.search(r"operator\s*$", header[:start]):
            continue  # the '()' of operator()
        m = NAME_BEFORE_PAREN.search(header[:start])
        if not m:
            continue
        name = re.sub(r"\s+", "", m.group(1)) if "operator" not in m.group(1) else \
            re.sub(r"\s*::\s*", "::", m.group(1).strip())
        if name.split("::")[-1] in NOT_NAMES:
            continue
        return name, m.start(1)
    return None


def classify(header):
    """What a '{' at namespace or class scope opens: ('namespace', name),
    ('class', name), ('function', (name, offset)) or ('other', None)."""
    body = strip_template_prefix(header)
    flat = body
    for start, end in reversed(top_level(body)):
        flat = flat[:start] + "(" + " " * (end - start - 1) + ")" + flat[end + 1:]
    m = re.search(r"\bnamespace\b\s*([\w:]*)\s*$", flat)
    if m:
        return "namespace", m.group(1)
    if re.match(r'\s*extern\s*"\s*"\s*$', flat):
        return "namespace", ""
    m = re.match(r"\s*(?:\w+\s+)*?(class|struct|union|enum)\b(?:\s+(?:class|struct))?"
                 r"((?:\s+[A-Za-z_][\w:]*(?:<[^{]*?>)?)*)", flat)
    if m and "(" not in flat[:m.end()] and "=" not in flat:
        names = [w for w in m.group(2).split() if w not in ("final", "alignas")]
        kind = "enum" if m.group(1) == "enum" else "class"
        return kind, names[-1] if names else ""
    if re.search(r"(?<![=!<>+\-*/%&|^])=(?!=)", re.sub(r"operator\s*\S+?\s*\(", "f(", flat)):
        return "other", None
    found = function_name(body)
    if found:
        name, offset = found
        return "function", (name, offset + len(header) - len(body))
    return "other", None


class Function:
    def __init__(self, path, line, name, length):
        self.path, self.line, self.name, self.length = path, line, name, length


def functions_in(path, text):
    """Every function body in one source text."""
    code = blank_non_code(text)
    line_of = []
    line = 1
    for ch in code:
        line_of.append(line)
        if ch == "\n":
            line += 1
    line_of.append(line)
    found = []
    scopes = []          # (kind, name, close position) of the enclosing namespaces/classes
    header_start = 0
    paren_depth = 0
    k = 0
    n = len(code)
    while k < n:
        ch = code[k]
        if ch == "(":
            paren_depth += 1
        elif ch == ")":
            paren_depth = max(0, paren_depth - 1)
        elif ch == ";" and paren_depth == 0:
            header_start = k + 1
        elif ch == "}":
            if scopes:
                scopes.pop()
            header_start = k + 1
            paren_depth = 0
        elif ch == "{":
            header = code[header_start:k]
            close = match_brace(code, k)
            if paren_depth > 0 or is_member_initializer(header):
                k = close + 1  # a brace initialiser inside the header: part of it
                continue
            kind, what = classify(header)
            if kind in ("namespace", "class"):
                scopes.append((kind, what, close))
                header_start = k + 1
            elif kind == "function":
                name, offset = what
                prefix = [s[1] for s in scopes if s[1]]  # anonymous namespaces and classes add nothing
                qualified = "::".join(prefix + [name])
                start_line = line_of[header_start + offset]
                found.append(Function(path, start_line, qualified, line_of[close] - start_line + 1))
                k = close + 1
                header_start = k
                continue
            else:
                k = close + 1  # enum body or initialiser: the header goes on to ';'
                continue
        k += 1
    return found


def is_member_initializer(header):
    """True when header is a constructor's signature with a member-initialiser
    list and the '{' that follows it opens a member's brace initialiser."""
    body = strip_template_prefix(header)
    groups = top_level(body)
    if not groups:
        return False
    first_end = groups[0][1] if function_name(body) else None
    if first_end is None:
        return False
    tail = body[first_end + 1:]
    if not re.match(r"\s*(?:noexcept\s*)?:(?!:)", tail):
        return False
    return bool(re.search(r"[\w>]\s*$", body))


def scan(paths):
    found = []
    for root in paths:
        if os.path.isfile(root):
            files = [root]
        else:
            files = []
            for dirpath, dirnames, filenames in os.walk(root):
                dirnames.sort()
                files += [os.path.join(dirpath, f) for f in sorted(filenames)
                          if f.endswith(SOURCE_SUFFIXES)]
        for path in files:
            with open(path, encoding="utf-8", errors="replace") as f:
                found += functions_in(os.path.relpath(path, REPO_DIR) if path.startswith(REPO_DIR) else path,
                                      f.read())
    return found


def report(found, top, over, out):
    longest = sorted(found, key=lambda f: (-f.length, f.path, f.line))
    over60 = sum(1 for f in found if f.length > 60)
    over100 = sum(1 for f in found if f.length > 100)
    total = len(found)
    share = (lambda c: 100.0 * c / total if total else 0.0)
    out.write(f"functions: {total}\n")
    out.write(f"over 60 lines: {over60} ({share(over60):.1f} %)\n")
    out.write(f"over 100 lines: {over100} ({share(over100):.1f} %)\n")
    if over is not None:
        listed = [f for f in longest if f.length > over]
        out.write(f"\nover {over} lines ({len(listed)}):\n")
    else:
        listed = longest[:top]
        out.write(f"\nlongest {len(listed)}:\n")
    for f in listed:
        out.write(f"{f.length:5d}  {f.name}  {f.path}:{f.line}\n")


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--paths", nargs="+", default=[os.path.join(REPO_DIR, "src")],
                        help="folders or files to scan (default: src/ of this repository)")
    parser.add_argument("--top", type=int, default=15, help="how many of the longest to list")
    parser.add_argument("--over", type=int, help="list every function longer than this many lines")
    args = parser.parse_args(argv)
    missing = [p for p in args.paths if not os.path.exists(p)]
    if missing:
        sys.stderr.write(f"function_census.py: no such path: {', '.join(missing)}\n")
        return 2
    report(scan(args.paths), args.top, args.over, sys.stdout)
    return 0


if __name__ == "__main__":
    sys.exit(main())
