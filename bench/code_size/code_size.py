#!/usr/bin/env python3
"""The size of the library's code at a commit: lines of code under bake/
(C++ lines that are neither blank nor comments) per folder, and the
functions longer than a limit (their definition's first to last line, by
Universal Ctags; lambdas are left out: they count in their function).

    bench/code_size/code_size.py [REV ...] [--limit 100] [--list]

REV: a commit (default HEAD), read with `git show` (no checkout). Prints a
Markdown table with a column per commit.
"""
import argparse
import os
import re
import subprocess
import sys
import tempfile

ROOT = subprocess.run(["git", "rev-parse", "--show-toplevel"], capture_output=True, text=True,
                      cwd=os.path.dirname(os.path.abspath(__file__)), check=True).stdout.strip()


def git(*args):
    return subprocess.run(["git", *args], capture_output=True, text=True, cwd=ROOT,
                          check=True).stdout


def code_lines(text):
    """Lines with code: not blank, not inside or only a comment."""
    count, in_block = 0, False
    for line in text.splitlines():
        s = line.strip()
        code = False
        while s:
            if in_block:
                end = s.find("*/")
                if end < 0:
                    s = ""
                    break
                s, in_block = s[end + 2:].strip(), False
                continue
            if s.startswith("//"):
                break
            if s.startswith("/*"):
                in_block, s = True, s[2:]
                continue
            code = True
            break
        count += code
    return count


def measure(rev, limit):
    files = [f for f in git("ls-tree", "-r", "--name-only", rev, "bake").split()
             if f.endswith((".cpp", ".h"))]
    per_folder, long_functions = {}, []
    with tempfile.TemporaryDirectory() as tmp:
        for f in files:
            text = git("show", f"{rev}:{f}")
            folder = f.split("/")[1] if f.count("/") > 1 else "."
            per_folder[folder] = per_folder.get(folder, 0) + code_lines(text)
            path = os.path.join(tmp, f)
            os.makedirs(os.path.dirname(path), exist_ok=True)
            with open(path, "w") as out:
                out.write(text)
        tags = subprocess.run(["ctags", "-R", "--languages=C++", "--c++-kinds=f",
                               "--fields=+ne", "-o", "-", "bake"], capture_output=True,
                              text=True, cwd=tmp, check=True).stdout
    for line in tags.splitlines():
        name, path = line.split("\t")[:2]
        if name.startswith("__anon"):
            continue  # a lambda
        start = re.search(r"\tline:(\d+)", line)
        end = re.search(r"\tend:(\d+)", line)
        if start and end:
            n = int(end.group(1)) - int(start.group(1)) + 1
            if n > limit:
                long_functions.append((n, f"{path}:{start.group(1)} {name}"))
    return per_folder, sorted(long_functions, reverse=True)


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("revs", nargs="*", default=["HEAD"])
    parser.add_argument("--limit", type=int, default=100)
    parser.add_argument("--list", action="store_true", help="list the long functions")
    args = parser.parse_args()
    results = [(rev, *measure(rev, args.limit)) for rev in args.revs]
    folders = sorted({f for _, per, _ in results for f in per})
    print("| bake/ | " + " | ".join(git("rev-parse", "--short", r).strip() for r in args.revs) + " |")
    print("|---|" + "---|" * len(args.revs))
    for f in folders:
        print(f"| {f} | " + " | ".join(str(per.get(f, 0)) for _, per, _ in results) + " |")
    print("| **all** | " + " | ".join(str(sum(per.values())) for _, per, _ in results) + " |")
    print(f"| functions over {args.limit} lines | " +
          " | ".join(str(len(lf)) for _, _, lf in results) + " |")
    if args.list:
        for rev, _, lf in results:
            print(f"\n{rev}:")
            for n, where in lf:
                print(f"  {n:4d}  {where}")


if __name__ == "__main__":
    sys.exit(main())
