#!/usr/bin/env python3
"""Doxygen INPUT_FILTER for include/granary.h (make docs).

The header documents itself in plain C comments, which Doxygen does not read. This filter turns
them into Doxygen comments on the fly; the header itself is not changed. A comment block that
stands right above a declaration documents it (``/*`` -> ``/**``); a comment after code on the
same line documents that line's member, enum constant or function (``/*`` -> ``/**<``); the first
comment of the file becomes the file's description. Section banners (``/* ----``) stay plain
comments. Characters that Doxygen would read as commands or HTML (``< > @ \\ % # &``) are escaped
in the comment text. Line numbers are kept."""
import re
import sys

ESCAPE = re.compile(r"([<>@\\%#&$])")


def esc(text):
    return ESCAPE.sub(r"\\\1", text)


def escape_comment(line, start):
    """Escape the comment text of `line` from column `start` (just after the opener) on."""
    head, body = line[:start], line[start:]
    if "*/" in body:
        text, tail = body.split("*/", 1)
        return head + esc(text) + "*/" + tail
    return head + esc(body)


def escape_continuation(line):
    m = re.match(r"^(\s*\*?)(.*)$", line)
    body = m.group(2)
    if "*/" in body:
        text, tail = body.split("*/", 1)
        return m.group(1) + esc(text) + "*/" + tail
    return m.group(1) + esc(body)


def main(path):
    with open(path, encoding="utf-8") as f:
        lines = f.read().split("\n")
    out = list(lines)
    i, n = 0, len(lines)
    while i < n:
        line = lines[i]
        stripped = line.lstrip()
        # a comment block that starts a line
        if stripped.startswith("/*") and not stripped.startswith(("/**", "/*!")):
            j = i
            while "*/" not in lines[j] and j + 1 < n:
                j += 1
            banner = stripped.startswith("/* --")
            nxt = lines[j + 1] if j + 1 < n else ""
            after = lines[j].split("*/", 1)[1].strip() if "*/" in lines[j] else ""
            doc = False
            if i == 0 and stripped.rstrip() == "/*":
                out[i] = line.replace("/*", "/** @file", 1)
                doc = True
            elif not banner and not after and nxt.strip() and not nxt.lstrip().startswith(
                    ("/*", "#define", "#if", "#endif", "#include", "#undef")):
                col = line.index("/*") + 2
                out[i] = escape_comment(line[:col] + "*" + line[col:], col + 1)
                doc = True
            if doc:
                for k in range(i + 1, j + 1):
                    out[k] = escape_continuation(lines[k])
            i = j + 1
            continue
        # a comment after code on the same line
        m = re.match(r"^(\s*\S.*?)(/\*)(?![*!<])(.*)$", line)
        if m and not m.group(1).lstrip().startswith(("*", "//", "#")) and '"' not in m.group(1):
            out[i] = escape_comment(m.group(1) + "/**<" + m.group(3), len(m.group(1)) + 4)
            if "*/" not in line:
                j = i + 1
                while j < n and "*/" not in lines[j]:
                    out[j] = escape_continuation(lines[j])
                    j += 1
                if j < n:
                    out[j] = escape_continuation(lines[j])
                i = j + 1
                continue
        i += 1
    sys.stdout.write("\n".join(out))


if __name__ == "__main__":
    main(sys.argv[1])
