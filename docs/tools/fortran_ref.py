#!/usr/bin/env python3
"""fortran_ref.py MODULE.f90 - Markdown list of the public procedures of the Fortran module
(make docs): for each public subroutine or function, its argument list with the declared type and
intent of each dummy argument, and the `!>` comment above it. Private helpers are left out."""
import re
import sys


def main(path):
    src = open(path, encoding="utf-8").read()
    # public names: `public :: a, b, &` lines (continuations included)
    public = set()
    for m in re.finditer(r"^\s*public\s*::\s*((?:[^\n]*&\s*\n)*[^\n]*)", src, re.M):
        for name in re.split(r"[,&\s]+", m.group(1)):
            if name:
                public.add(name.lower())
    lines = src.split("\n")
    procs = []
    i = 0
    head = re.compile(r"^\s*(?:(?:pure|elemental|recursive|impure)\s+)*(?:(?:integer|real|logical|character)[^:]*?\s+)?"
                      r"(subroutine|function)\s+(gran_\w+)\s*\(([^)]*)\)?", re.I)
    while i < len(lines):
        m = head.match(lines[i])
        if not m or m.group(2).lower() not in public or "bind(" in lines[i].lower():
            i += 1
            continue
        kind, name = m.group(1).lower(), m.group(2)
        # the argument list may continue over lines
        text, j = lines[i], i
        while text.rstrip().endswith("&") and j + 1 < len(lines):
            j += 1
            text = text.rstrip()[:-1] + lines[j].strip().lstrip("&")
        am = re.search(r"\(([^)]*)\)", text)
        args = [a.strip() for a in am.group(1).split(",")] if am and am.group(1).strip() else []
        # the doc comment above
        doc, k = [], i - 1
        while k >= 0 and lines[k].strip().startswith("!"):
            c = lines[k].strip()
            if c.startswith("!>") or c.startswith("!!"):
                doc.insert(0, c[2:].strip())
            k -= 1
        # declarations of the dummies until `end subroutine`
        decl = {}
        k = j + 1
        while k < len(lines) and not re.match(r"^\s*end\s+(subroutine|function)", lines[k], re.I):
            dm = re.match(r"^\s*([^!:]+?)\s*::\s*(.+)$", lines[k])
            if dm:
                typ = re.sub(r"\s+", " ", dm.group(1).strip())
                for part in re.split(r",(?![^()]*\))", dm.group(2)):
                    nm = re.match(r"\s*(\w+)\s*(\([^)]*\))?", part)
                    if nm and nm.group(1).lower() not in decl:
                        decl[nm.group(1).lower()] = (typ, nm.group(2) or "")
            k += 1
        procs.append((name, kind, args, decl, " ".join(doc)))
        i = k + 1
    procs.sort(key=lambda p: p[0])
    out = ["| procedure | arguments | what it does |", "| --- | --- | --- |"]
    for name, kind, args, decl, doc in procs:
        parts = []
        for a in args:
            typ, shape = decl.get(a.lower(), ("", ""))
            opt = ", optional" in typ
            typ = typ.replace(", optional", "")
            s = "`%s%s`: %s" % (a, shape, typ) if typ else "`%s`" % a
            parts.append(("[%s]" % s) if opt else s)
        desc = doc.replace("|", "\\|").replace("<", "&lt;") or ("function" if kind == "function" else "")
        out.append("| `%s` | %s | %s |" % (name, "; ".join(parts).replace("|", "\\|"), desc))
    sys.stdout.write("\n".join(out) + "\n\n%d public procedures.\n" % len(procs))


if __name__ == "__main__":
    main(sys.argv[1])
