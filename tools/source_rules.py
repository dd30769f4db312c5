#!/usr/bin/env python3
"""The project's source rules, checked on the tracked files (git ls-files).

  C++ files (.cpp .h .hpp .cc) in engine/, passes/, editor/, tools/: at most 600 lines.
  Shaders (every file under shaders/ with a shader extension):       at most 700 lines.
  Functions in those C++ files and shaders:                           at most 120 lines.
  No tracked text file cites the design or oracles files kept outside the repository, or the
  shared folder beside it: the repository stands alone (docs/oracles.md and docs/lavapipe.md hold
  the copies a reader needs).

A function is a brace-enclosed definition at namespace or class scope whose head is a parameter
list followed only by qualifiers, a trailing return type or a constructor's initializer list. Its
length runs from the first line of its head (template and attribute lines included) to its closing
brace. Comments, string, character and raw-string literals and preprocessor lines are blanked
before the scan, so braces inside them do not count. An initializer of data (`... = {`, `T x{...}`)
is not a function, and neither is a lambda bound to a name at namespace scope (it is data too).

Tables: a function that is in truth a table (its body is one literal of data, and splitting it
would only scatter the data) is exempt when the line just before its head is the comment

    // source-rules: table

Usage:
  tools/source_rules.py [--root DIR]           print each breach as file:line: message; exit 0 if
                                               none, 1 if any, 2 on a usage error
  tools/source_rules.py --report [--root DIR]  print the longest file and the longest function of
                                               each top-level folder with their sizes; exit 0
"""

import argparse
import os
import re
import subprocess
import sys

CPP_FOLDERS = ("engine", "passes", "editor", "tools")
CPP_EXTENSIONS = (".cpp", ".h", ".hpp", ".cc")
SHADER_FOLDER = "shaders"
SHADER_EXTENSIONS = (".glsl", ".comp", ".frag", ".vert", ".geom", ".tesc", ".tese", ".rgen", ".rchit", ".rmiss", ".rahit",
                     ".rint", ".rcall", ".mesh", ".task", ".h", ".inc")
REPORT_FOLDERS = CPP_FOLDERS + (SHADER_FOLDER,)
MAX_CPP_FILE = 600
MAX_SHADER_FILE = 700
MAX_FUNCTION = 120
TABLE_MARKER = "// source-rules: table"
# Spelled in pieces so that this script, which must name them, does not cite them itself.
CITED_OUTSIDE = [re.compile(p) for p in (r"\bDESIGN" + r"\.md\b", r"\bORACLES" + r"\.md\b", r"\.\./" + r"shared\b")]


def blank_code(text):
    """The text with comments, literals and preprocessor lines replaced by spaces (newlines kept)."""
    out = []
    i, n = 0, len(text)
    at_line_start = True
    while i < n:
        c = text[i]
        if c == "\n":
            out.append(c)
            i += 1
            at_line_start = True
            continue
        if at_line_start and c in " \t":
            out.append(c)
            i += 1
            continue
        if at_line_start and c == "#":
            # A preprocessor line, continuations included.
            while i < n and text[i] != "\n":
                if text[i] == "\\" and i + 1 < n and text[i + 1] == "\n":
                    out.append(" \n")
                    i += 2
                    continue
                out.append(" ")
                i += 1
            continue
        at_line_start = False
        if text.startswith("//", i):
            while i < n and text[i] != "\n":
                out.append(" ")
                i += 1
            continue
        if text.startswith("/*", i):
            end = text.find("*/", i + 2)
            end = n if end < 0 else end + 2
            out.append(re.sub(r"[^\n]", " ", text[i:end]))
            i = end
            continue
        raw = re.match(r'(?:u8|u|U|L)?R"([^()\\ \n]{0,16})\(', text[i:i + 24])
        if raw and (i == 0 or not (text[i - 1].isalnum() or text[i - 1] == "_")):
            closing = ")" + raw.group(1) + '"'
            end = text.find(closing, i + raw.end())
            end = n if end < 0 else end + len(closing)
            out.append(re.sub(r"[^\n]", " ", text[i:end]))
            i = end
            continue
        if c in "\"'":
            if c == "'" and i > 0 and text[i - 1].isalnum():
                # A digit separator (1'000'000), not a character literal.
                out.append(" ")
                i += 1
                continue
            j = i + 1
            while j < n and text[j] != c and text[j] != "\n":
                j += 2 if text[j] == "\\" else 1
            end = min(j + 1, n)
            out.append(c + re.sub(r"[^\n]", " ", text[i + 1:end - 1]) + (c if end - 1 > i else ""))
            i = end
            continue
        out.append(c)
        i += 1
    return "".join(out)


def matching_close(text, start, opening, closing):
    """Index of the bracket that closes the one at text[start], or -1."""
    depth = 0
    for k in range(start, len(text)):
        if text[k] == opening:
            depth += 1
        elif text[k] == closing:
            depth -= 1
            if depth == 0:
                return k
    return -1


QUALIFIERS = re.compile(r"\s*(?:const|volatile|noexcept\s*(?:\([^()]*\))?|override|final|mutable|&&|&|try)\b\s*|\s*&&?\s*")
TRAILING_RETURN = re.compile(r"\s*->\s*[\w:<>,\s*&\[\]]+$")
CONTROL = {"if", "for", "while", "switch", "catch", "do", "else", "return", "sizeof", "decltype", "alignas", "static_assert"}


def simplify_head(head):
    """The head with the parts that would mislead the shape tests removed."""
    head = re.sub(r"\boperator\s*\(\s*\)", "operator_call", head)
    head = re.sub(r"\boperator\s*(?:new|delete)(?:\s*\[\s*\])?", "operator_alloc", head)
    head = re.sub(r"\boperator\s*[^\w\s(]+", "operator_symbol", head)
    head = re.sub(r"\[\[.*?\]\]", " ", head)
    head = re.sub(r"^\s*(?:(?:public|private|protected)\s*:(?!:)\s*)+", "", head)
    while True:
        m = re.match(r"\s*template\s*<", head)
        if not m:
            break
        close = matching_close(head, m.end() - 1, "<", ">")
        if close < 0:
            break
        head = head[close + 1:]
    return head


def top_level_equals(text):
    depth = 0
    for c in text:
        if c in "([<":
            depth += 1
        elif c in ")]>":
            depth -= 1
        elif c == "=" and depth == 0:
            return True
    return False


def function_shape(head):
    """(name, initializer list pending) when the head declares a function definition, else None."""
    head = simplify_head(head)
    open_paren = head.find("(")
    if open_paren < 0 or top_level_equals(head[:open_paren]):
        return None
    name = re.search(r"([~\w:]+)\s*$", head[:open_paren])
    if not name or name.group(1).split("::")[-1] in CONTROL:
        return None
    shown = re.sub(r"operator_\w+", "operator", name.group(1))
    close = matching_close(head, open_paren, "(", ")")
    if close < 0:
        return None
    tail = head[close + 1:]
    while True:
        m = QUALIFIERS.match(tail)
        if not m or m.end() == 0:
            break
        tail = tail[m.end():]
    if tail.strip() == "" or TRAILING_RETURN.match(tail):
        return shown, False
    if re.match(r"\s*:(?!:)", tail):
        return shown, True
    return None


def line_of(text, index, starts):
    """1-based line number of text[index], from the sorted line-start offsets."""
    lo, hi = 0, len(starts)
    while lo + 1 < hi:
        mid = (lo + hi) // 2
        if starts[mid] <= index:
            lo = mid
        else:
            hi = mid
    return lo + 1


def functions_in(text):
    """Every function definition at namespace or class scope: (name, first line, last line)."""
    code = blank_code(text)
    starts = [0] + [m.end() for m in re.finditer("\n", code)]
    original_lines = text.split("\n")
    found = []
    scopes = []  # "namespace", "class" or "other" for each open brace
    head_start = 0
    i = 0
    while i < len(code):
        c = code[i]
        if c in ";}":
            if c == "}" and scopes:
                scopes.pop()
            head_start = i + 1
        elif c == "{":
            head = code[head_start:i]
            at_outer = all(s in ("namespace", "class") for s in scopes)
            kind = "other"
            if at_outer:
                if re.match(r"\s*(?:inline\s+)?namespace\b", head) or re.match(r"\s*extern\s*\"\s*\"\s*$", head):
                    kind = "namespace"
                elif re.match(r"\s*(?:template\s*<.*>\s*)?(?:class|struct|union)\b", head, re.S) and not top_level_equals(head):
                    kind = "class"
                else:
                    shape = function_shape(head)
                    before = code[:i].rstrip()
                    if shape and shape[1] and before and (before[-1].isalnum() or before[-1] in "_>"):
                        # A member's brace initializer inside a constructor's initializer list.
                        end = matching_close(code, i, "{", "}")
                        i = len(code) if end < 0 else end + 1
                        continue
                    if shape:
                        end = matching_close(code, i, "{", "}")
                        first = line_of(code, head_start + len(head) - len(head.lstrip()), starts)
                        last = line_of(code, end if end >= 0 else len(code) - 1, starts)
                        marked = first >= 2 and original_lines[first - 2].strip() == TABLE_MARKER
                        if not marked:
                            found.append((shape[0], first, last))
                        i = len(code) if end < 0 else end + 1
                        head_start = i
                        continue
            scopes.append(kind)
            head_start = i + 1
        i += 1
    return found


def tracked_files(root):
    try:
        listed = subprocess.run(["git", "-C", root, "ls-files", "-z"], check=True, capture_output=True).stdout
    except (OSError, subprocess.CalledProcessError) as error:
        sys.exit(f"source_rules: {root} is not a git checkout (git ls-files failed: {error})")
    return [p for p in listed.decode().split("\0") if p]


def read_text(path):
    """The file's text, or None for a binary file or one that is not there (a deleted, unstaged file)."""
    try:
        with open(path, "rb") as f:
            data = f.read()
    except OSError:
        return None
    if b"\0" in data[:8192]:
        return None
    try:
        return data.decode("utf-8")
    except UnicodeDecodeError:
        return None


def line_count(text):
    return text.count("\n") + (0 if text.endswith("\n") or not text else 1)


def kind_of(path):
    top = path.split("/", 1)[0]
    if top in CPP_FOLDERS and path.endswith(CPP_EXTENSIONS):
        return "cpp"
    if top == SHADER_FOLDER and path.endswith(SHADER_EXTENSIONS):
        return "shader"
    return None


def measure(root):
    """For each tracked file: (path, kind, lines, functions, citations)."""
    results = []
    for path in tracked_files(root):
        text = read_text(os.path.join(root, path))
        if text is None:
            continue
        kind = kind_of(path)
        citations = []
        for number, line in enumerate(text.split("\n"), 1):
            for pattern in CITED_OUTSIDE:
                m = pattern.search(line)
                if m:
                    citations.append((number, m.group(0)))
        functions = functions_in(text) if kind else []
        results.append((path, kind, line_count(text), functions, citations))
    return results


def breaches(results):
    found = []
    for path, kind, lines, functions, citations in results:
        limit = {"cpp": MAX_CPP_FILE, "shader": MAX_SHADER_FILE}.get(kind)
        if limit and lines > limit:
            found.append(f"{path}:1: {lines} lines (a {'C++ file' if kind == 'cpp' else 'shader'} has at most {limit})")
        for name, first, last in functions:
            length = last - first + 1
            if length > MAX_FUNCTION:
                found.append(f"{path}:{first}: function {name} is {length} lines (at most {MAX_FUNCTION})")
        for number, cited in citations:
            found.append(f"{path}:{number}: cites {cited}, which is outside the repository")
    return found


def report(results):
    for folder in REPORT_FOLDERS:
        mine = [r for r in results if r[1] and r[0].startswith(folder + "/")]
        if not mine:
            print(f"{folder}: no files")
            continue
        longest_file = max(mine, key=lambda r: r[2])
        functions = [(last - first + 1, name, path, first) for path, _, _, fs, _ in mine for name, first, last in fs]
        print(f"{folder}: longest file {longest_file[0]} ({longest_file[2]} lines)", end="")
        if functions:
            length, name, path, first = max(functions)
            print(f"; longest function {name} at {path}:{first} ({length} lines)")
        else:
            print("; no functions")


def main():
    parser = argparse.ArgumentParser(description="Check the tracked sources against the project's size and citation rules.")
    parser.add_argument("--root", default=os.path.dirname(os.path.dirname(os.path.abspath(__file__))),
                        help="the repository to check (default: the one this script is in)")
    parser.add_argument("--report", action="store_true", help="print the longest file and function per top-level folder")
    args = parser.parse_args()
    results = measure(args.root)
    if args.report:
        report(results)
        return 0
    found = breaches(results)
    for line in found:
        print(line)
    if found:
        print(f"source_rules: {len(found)} breach(es) of the source rules (tools/source_rules.py)", file=sys.stderr)
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main())
