#!/usr/bin/env python3
"""lint.py [ROOT]: ffdtool's own source checks, run by ctest (the `lint` test).

Prints one line per violation, `file:line: what`, and exits 1 if there is any.

Rules:
  nlohmann-include  no #include of <nlohmann/...> in lib/ outside lib/script: algorithms
                    take options structs and never see JSON (docs/architecture.md, "Typed steps").
                    lib/batch writes JSON logs (the results log, the report) and may too,
                    as may the glTF writer, which edits glTF's own JSON;
                    apps/ and tests/ may use JSON.
  layer-include     a folder of lib/ includes only itself and the folders below it (LAYERS,
                    docs/architecture.md "Layers"); lib/CMakeLists.txt's layer checks
                    enforce the same at link time.
  json-pointer      no JSON-pointer string literal ("/support", "/k": a "/" and then a
                    lowercase letter or underscore) in the code of the algorithm folders
                    (POINTER_DIRS); the script layer adds the place. Comments do not count,
                    nor absolute file-system paths ("/proc/", "/tmp/", ...).
  long-function     no function body longer than MAX_FUNCTION_LINES lines in lib/, apps/ and python/,
                    counted from its "{" line to its "}" line; lambdas and initializers
                    inside a function count toward it.
  contract-pch      in a CMakeLists.txt, a set_source_files_properties() that compiles
                    files with -ffp-contract=off also sets SKIP_PRECOMPILE_HEADERS ON: GCC
                    takes the optimization options a precompiled header was built with
                    over the file's own, so the option would silently do nothing.

The reader is a small brace matcher over the source with comments, string and character
literals and preprocessor lines blanked out. At namespace or class scope a "{" opens a
function body when what precedes it (since the last ";", "{" or "}") ends in a parameter
list, optionally followed by qualifiers (const, noexcept, override, -> type, ...) or a
constructor's member initializers, or when it is a lambda assigned to a variable. Other
braces there (namespace, class, enum, extern "C", brace initializers) are not functions.
"""
import os
import re
import sys

MAX_FUNCTION_LINES = 80
SOURCE_SUFFIXES = (".cpp", ".cc", ".cxx", ".h", ".hpp")
SCAN_DIRS = ("lib", "apps", "python")  # every rule's folders lie inside these
FUNCTION_DIRS = ("lib", "apps", "python")
NLOHMANN_DIRS = ("lib",)
# The glTF writer edits glTF JSON itself (a file format that is JSON, not a script).
NLOHMANN_EXEMPT = ("lib/script", "lib/batch", "lib/mesh/gltf_write.cpp", "lib/mesh/gltf_document.cpp")
# Each folder of lib/ and the folders it may include (besides itself).
LAYERS = {
    "common": set(),
    "mesh": {"common"},
    "warp": {"common", "mesh"},
    "multires": {"common", "mesh", "warp"},
    "bcm": {"common", "mesh"},
    "remesh": {"common", "mesh", "warp"},
    "render": {"common", "mesh", "warp", "remesh"},
    "script": {"common", "mesh", "warp", "multires", "bcm", "remesh", "render"},
    "batch": {"common", "mesh", "warp", "multires", "bcm", "remesh", "render", "script"},
}
POINTER_DIRS = ("lib/common", "lib/mesh", "lib/warp", "lib/remesh", "lib/bcm", "lib/multires")
FILESYSTEM_PREFIXES = ("/proc/", "/dev/", "/tmp/", "/usr/", "/etc/", "/sys/", "/var/", "/opt/", "/home/")

# Known long functions, "file: function" -> why it is allowed for now. Remove an entry
# when the function is split; an entry that matches nothing is reported as a note.
LONG_FUNCTION_ALLOWLIST = {
}

# Folders exempt from the json-pointer rule, folder -> why (none: the rule holds everywhere).
JSON_POINTER_ALLOWLIST = {}


def strip_source(text):
    """Returns (code, literals): `code` is `text` with comments, string and character
    literals blanked (newlines kept, a literal becomes "" or ''), `literals` the string
    literals as (line, content) in order."""
    out = []
    literals = []
    i, n, line = 0, len(text), 1
    while i < n:
        c = text[i]
        if c == "\n":
            out.append(c)
            line += 1
            i += 1
        elif text.startswith("//", i):
            j = text.find("\n", i)
            i = n if j < 0 else j
        elif text.startswith("/*", i):
            j = text.find("*/", i + 2)
            j = n if j < 0 else j + 2
            newlines = text.count("\n", i, j)
            out.append(" " + "\n" * newlines)
            line += newlines
            i = j
        elif c == '"' or (c == "R" and text.startswith('R"', i) and not _ident_before(text, i)):
            if c == "R":  # raw string R"delim( ... )delim"
                open_paren = text.find("(", i + 2)
                delim = text[i + 2:open_paren]
                close = text.find(")" + delim + '"', open_paren + 1)
                close = n if close < 0 else close
                content = text[open_paren + 1:close]
                j = min(n, close + len(delim) + 2)
            else:
                j = i + 1
                while j < n and text[j] != '"' and text[j] != "\n":
                    j += 2 if text[j] == "\\" else 1
                content = text[i + 1:j]
                j += 1
            literals.append((line, content))
            newlines = text.count("\n", i, j)
            out.append('""' + "\n" * newlines)
            line += newlines
            i = j
        elif c == "'" and not (i > 0 and text[i - 1].isalnum() and i + 1 < n and text[i + 1].isalnum()
                               and _digit_separator(text, i)):
            j = i + 1
            while j < n and text[j] != "'" and text[j] != "\n":
                j += 2 if text[j] == "\\" else 1
            out.append("''")
            i = j + 1
        else:
            out.append(c)
            i += 1
    return "".join(out), literals


def _ident_before(text, i):
    """True if text[i] continues an identifier (so R"..." is not a raw-string prefix),
    allowing the encoding prefixes u8R, uR, UR and LR."""
    j = i
    while j > 0 and (text[j - 1].isalnum() or text[j - 1] == "_"):
        j -= 1
    return text[j:i] not in ("", "u8", "u", "U", "L")


def _digit_separator(text, i):
    """True if the ' at i sits inside a number literal (C++14 digit separator, 1'000)."""
    j = i
    while j > 0 and (text[j - 1].isalnum() or text[j - 1] in "._'"):
        j -= 1
    return text[j].isdigit()


def blank_preprocessor(code):
    """Blanks preprocessor lines (with their continuations), keeping line numbers."""
    lines = code.split("\n")
    continued = False
    for k, l in enumerate(lines):
        if continued or l.lstrip().startswith("#"):
            continued = l.rstrip().endswith("\\")
            lines[k] = ""
    return "\n".join(lines)


SCOPE_KEYWORD = re.compile(r"\b(namespace|class|struct|union|enum|extern)\b")
QUALIFIERS = re.compile(r"^\s*((const|volatile|noexcept|override|final|mutable|&&|&|throw\s*\(\s*\))\s*"
                        r"|noexcept\s*\([^()]*\)\s*|->\s*[^{};]*?)*$")
CTOR_INIT = re.compile(r"^\s*(noexcept\s*(\(\))?\s*)?:(?!:)")
OPERATOR = re.compile(r"\boperator\s*(\(\s*\)|\[\s*\]|[^\s\w(]+|\w[\w\s:<>*&]*?(?=\())")


def remove_template_parameters(s):
    """`s` without the parameter lists of "template <...>" (balanced angle brackets)."""
    out, i = [], 0
    for m in re.finditer(r"\btemplate\s*<", s):
        if m.start() < i:
            continue
        out.append(s[i:m.start()] + " ")
        depth, j = 0, m.end() - 1
        while j < len(s):
            depth += {"<": 1, ">": -1}.get(s[j], 0)
            if depth == 0:
                break
            j += 1
        i = j + 1
    out.append(s[i:])
    return "".join(out)


def top_level(s):
    """`s` with the contents of (), [] and {} groups removed (the brackets kept)."""
    out, depth = [], 0
    for ch in s:
        if ch in "([{":
            if depth == 0:
                out.append(ch)
            depth += 1
        elif ch in ")]}":
            depth = max(0, depth - 1)
            if depth == 0:
                out.append(ch)
        elif depth == 0:
            out.append(ch)
    return "".join(out)


def classify(head):
    """What a "{" at namespace or class scope opens, from the text before it: ("scope",
    name), ("function", name), ("member-init", None) for a member's brace initializer in
    a constructor's initializer list, or ("data", None) for any other initializer."""
    h = re.sub(r"\b(public|private|protected)\s*:(?!:)", " ", head)
    h = remove_template_parameters(h)
    h = re.sub(r"\[\[.*?\]\]", " ", h)
    operators = []
    h = OPERATOR.sub(lambda m: operators.append(re.sub(r"\s+", "", m.group(0))) or f"operator_{len(operators) - 1} ", h)
    flat = top_level(h)
    first_paren = flat.find("(")
    before_paren = flat if first_paren < 0 else flat[:first_paren]
    scope = SCOPE_KEYWORD.search(before_paren)
    if scope:
        names = re.findall(r"[A-Za-z_]\w*", before_paren[scope.end():])
        return "scope", (names[0] if names and scope.group(1) in ("class", "struct", "union") else None)
    # A lambda assigned at namespace or class scope is a function body of its own.
    if re.search(r"(?<![=!<>])=(?!=)", flat):
        if re.search(r"\]\s*(\(\))?\s*(mutable\s*)?(->[^{]*)?$", flat.rstrip()):
            names = re.findall(r"([A-Za-z_]\w*)\s*=", flat)
            return "function", (names[-1] if names else "lambda")
        return "data", None
    if first_paren < 0:
        return "data", None
    tail = flat[first_paren + 2:]  # after the parameter list (its contents are gone)
    if CTOR_INIT.match(tail):
        # In a constructor's initializer list: "member{" is an initializer, ") {" or "} {"
        # the body.
        stripped = h.rstrip()
        if stripped and (stripped[-1].isalnum() or stripped[-1] in "_>"):
            return "member-init", None
    elif not QUALIFIERS.match(tail):
        return "data", None
    names = re.findall(r"((?:[A-Za-z_~]\w*\s*::\s*)*~?[A-Za-z_]\w*)\s*\($", flat[:first_paren + 1])
    name = re.sub(r"\s+", "", names[0]) if names else "?"
    return "function", re.sub(r"operator_(\d+)", lambda m: operators[int(m.group(1))], name)


def functions(code):
    """Yields (name, first line, line count) for each function body in `code` (comments,
    literals and preprocessor lines already blanked); names of members defined in a
    class body are prefixed with the class's name."""
    i, n, line = 0, len(code), 1
    head_start, head_line = 0, 1
    scopes = []  # class names (or None) of the open scopes
    paren = 0
    while i < n:
        c = code[i]
        if c == "\n":
            line += 1
        elif c in "([":
            paren += 1
        elif c in ")]":
            paren = max(0, paren - 1)
        elif c == ";" and paren == 0:
            head_start = i + 1
        elif c == "}":
            if scopes:
                scopes.pop()
            head_start = i + 1
        elif c == "{":
            kind, name = ("data", None) if paren else classify(code[head_start:i])
            if kind == "scope":
                scopes.append(name)
                head_start = i + 1
            else:
                end, end_line = match_brace(code, i, line)
                if kind == "function":
                    prefix = "".join(s + "::" for s in scopes if s)
                    qualified = name if "::" in name or not prefix else prefix + name
                    yield qualified, line, end_line - line + 1
                if kind == "function" or (kind == "data" and not paren):
                    head_start = end + 1
                i, line = end, end_line
        i += 1


def match_brace(code, i, line):
    """The index and line of the "}" matching the "{" at i (on `line`)."""
    depth = 0
    while i < len(code):
        c = code[i]
        if c == "\n":
            line += 1
        elif c == "{":
            depth += 1
        elif c == "}":
            depth -= 1
            if depth == 0:
                return i, line
        i += 1
    return len(code) - 1, line


def under(path, folders):
    return any(path == f or path.startswith(f + "/") for f in folders)


def source_files(root):
    """(path relative to root, full path) of every C++ source file the rules look at."""
    for top in SCAN_DIRS:
        base = os.path.join(root, top)
        for folder, dirs, files in os.walk(base):
            dirs.sort()
            for f in sorted(files):
                if f.endswith(SOURCE_SUFFIXES):
                    full = os.path.join(folder, f)
                    yield os.path.relpath(full, root).replace(os.sep, "/"), full


def check_includes(rel, code, literals):
    """nlohmann-include: #include <nlohmann/...> (or "nlohmann/...") lines."""
    quoted = {ln for ln, content in literals if content.startswith("nlohmann/")}
    for k, l in enumerate(code.split("\n"), 1):
        if re.match(r"\s*#\s*include\s*(<\s*nlohmann/|\"\")", l) and ("<" in l or k in quoted):
            yield f"{rel}:{k}: includes nlohmann outside lib/script (algorithms never see JSON)"


def check_layers(rel, code, literals):
    """layer-include: #include "folder/..." of a folder that is not below rel's."""
    parts = rel.split("/")
    if len(parts) < 3 or parts[0] != "lib" or parts[1] not in LAYERS:
        return
    lines = code.split("\n")
    for ln, content in literals:
        folder = content.split("/")[0]
        if not re.match(r"\s*#\s*include\s*\"\"", lines[ln - 1]) or folder not in LAYERS:
            continue
        if folder != parts[1] and folder not in LAYERS[parts[1]]:
            yield f"{rel}:{ln}: lib/{parts[1]} includes {content}, a folder above it (docs/architecture.md, Layers)"


def check_pointers(rel, literals, used):
    """json-pointer: string literals that look like a JSON pointer."""
    allowed = [d for d in JSON_POINTER_ALLOWLIST if under(rel, (d,))]
    for ln, content in literals:
        if not re.match(r"/[a-z_]", content) or content.startswith(FILESYSTEM_PREFIXES):
            continue
        if allowed:
            used.add(allowed[0])
            continue
        yield f"{rel}:{ln}: JSON pointer literal \"{content}\" (the script layer adds the place)"


def check_functions(rel, code, used):
    """long-function: function bodies longer than MAX_FUNCTION_LINES."""
    for name, start, count in functions(blank_preprocessor(code)):
        if count <= MAX_FUNCTION_LINES:
            continue
        key = f"{rel}: {name}"
        if key in LONG_FUNCTION_ALLOWLIST:
            used.add(key)
            continue
        yield f"{rel}:{start}: function {name} is {count} lines (at most {MAX_FUNCTION_LINES})"


def check_contract_pch(root):
    """contract-pch: set_source_files_properties(... -ffp-contract=off ...) without
    SKIP_PRECOMPILE_HEADERS ON, in the CMakeLists.txt files of the scanned folders."""
    for top in SCAN_DIRS + ("tests",):
        for folder, dirs, files in os.walk(os.path.join(root, top)):
            dirs.sort()
            if "CMakeLists.txt" not in files:
                continue
            full = os.path.join(folder, "CMakeLists.txt")
            rel = os.path.relpath(full, root).replace(os.sep, "/")
            with open(full, encoding="utf-8") as f:
                text = f.read()
            for call in re.finditer(r"set_source_files_properties\s*\(([^)]*)\)", text):
                body = call.group(1)
                if "-ffp-contract=off" in body and not re.search(r"SKIP_PRECOMPILE_HEADERS\s+ON", body):
                    line = text.count("\n", 0, call.start()) + 1
                    yield (f"{rel}:{line}: -ffp-contract=off without SKIP_PRECOMPILE_HEADERS ON "
                           "(the precompiled header's -ffp-contract=fast would win)")


def lint(root):
    """(violations, notes) for the tree at `root`; notes name allowlist entries that
    match nothing any more."""
    violations, used = [], set()
    for rel, full in source_files(root):
        with open(full, encoding="utf-8", errors="replace") as f:
            code, literals = strip_source(f.read())
        if under(rel, NLOHMANN_DIRS) and not under(rel, NLOHMANN_EXEMPT):
            violations += check_includes(rel, code, literals)
        violations += check_layers(rel, code, literals)
        if under(rel, POINTER_DIRS):
            violations += check_pointers(rel, literals, used)
        if under(rel, FUNCTION_DIRS):
            violations += check_functions(rel, code, used)
    violations += check_contract_pch(root)
    stale = [k for k in list(LONG_FUNCTION_ALLOWLIST) + list(JSON_POINTER_ALLOWLIST) if k not in used]
    return violations, [f"note: allowlist entry '{k}' matches nothing; remove it" for k in stale]


def main(argv):
    root = argv[1] if len(argv) > 1 else os.path.join(os.path.dirname(os.path.abspath(__file__)), "..")
    violations, notes = lint(os.path.abspath(root))
    for v in violations:
        print(v)
    for note in notes:
        print(note)
    if violations:
        print(f"lint: {len(violations)} violation(s)")
        return 1
    print("lint: clean")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
