#!/usr/bin/env python3
"""The source tree's house rules, checked (CI runs this before the tests):

* layers: engine <- geometry <- io <- analysis/model <- analysis/run, analysis/dynamics <-
  analysis/batch <- apps. A file includes project headers of its own folder or a lower layer
  only (engine knows no CGAL or VTK; a run knows no frequency analysis and no study;
  analysis no command);
* no include cycles between project headers;
* no source file over 350 lines;
* no function in engine/ or analysis/ over 80 lines unless a comment right above it says why.

Prints each breach with its file and line and exits 1 when there is any.
"""
import re
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
# From the bottom up; folders on one line are peers, which may not include each other.
LAYERS = [["engine"], ["geometry"], ["io"], ["analysis/model"], ["analysis/run", "analysis/dynamics"], ["analysis/batch"],
          ["apps"]]
FOLDERS = [folder for level in LAYERS for folder in level]


def level_of(folder):
    return next(i for i, level in enumerate(LAYERS) if folder in level)


def folder_of(path):
    """The layer folder of a project path ("analysis/run/seismic_run.h" -> "analysis/run"), or None."""
    parts = path.split("/")
    for depth in (2, 1):
        if "/".join(parts[:depth]) in FOLDERS and len(parts) > depth:
            return "/".join(parts[:depth])
    return None
MAX_FILE_LINES = 350
MAX_FUNCTION_LINES = 80
INCLUDE = re.compile(r'^\s*#\s*include\s+"([^"]+)"')
# The line that opens a function's body: its signature's end, ") {" (const, noexcept, a
# trailing return type allowed). A namespace-level function's signature starts at column 0.
BODY_OPENS = re.compile(r"\)\s*(const\s*)?(noexcept\s*)?(->\s*[^{]+)?\{\s*$")


def sources():
    for folder in FOLDERS:
        for path in sorted((ROOT / folder).glob("*")):
            if path.suffix in (".h", ".cpp"):
                yield folder, path
    for path in sorted((ROOT / "analysis").glob("*")):  # a file left beside the role folders
        if path.suffix in (".h", ".cpp"):
            yield "analysis", path


def main():
    breaches = []
    graph = {}
    for layer, path in sources():
        rel = path.relative_to(ROOT).as_posix()
        if layer == "analysis":
            breaches.append(f"{rel}: outside analysis's role folders (model, run, dynamics, batch)")
            continue
        lines = path.read_text().splitlines()
        if len(lines) > MAX_FILE_LINES:
            breaches.append(f"{rel}: {len(lines)} lines (at most {MAX_FILE_LINES}): split it by job")
        graph[rel] = []
        for number, line in enumerate(lines, 1):
            m = INCLUDE.match(line)
            if not m:
                continue
            target = m.group(1)
            target_folder = folder_of(target)
            if target_folder is None:
                continue  # a test helper or a generated header
            graph[rel].append(target)
            if target_folder != layer and level_of(target_folder) >= level_of(layer):
                order = " <- ".join(", ".join(level) for level in LAYERS)
                breaches.append(f"{rel}:{number}: includes {target}, of a higher layer or a peer ({order})")
        if layer == "engine" or layer.startswith("analysis"):
            breaches += long_functions(rel, lines)
    breaches += cycles(graph)
    for b in breaches:
        print(f"check_layout: {b}")
    print(f"check_layout: {len(graph)} files, {len(breaches)} breaches")
    return 1 if breaches else 0


def continues_signature(line):
    """A line above a function's opening line that belongs to its wrapped signature."""
    text = line.strip()
    return bool(text) and not text.startswith(("//", "#", "}")) and not text.endswith((";", "{", "}"))


def long_functions(rel, lines):
    found = []
    i = 0
    while i < len(lines):
        if BODY_OPENS.search(lines[i]):
            start = i  # walk up a wrapped signature to its first line
            while start > 0 and lines[start][:1] in (" ", "\t") and continues_signature(lines[start - 1]):
                start -= 1
            if re.match(r"[A-Za-z_]", lines[start]):
                end = i + 1
                while end < len(lines) and lines[end] != "}":
                    end += 1
                length = end - start + 1
                explained = start > 0 and lines[start - 1].lstrip().startswith("//")
                if length > MAX_FUNCTION_LINES and not explained:
                    found.append(f"{rel}:{start + 1}: a function of {length} lines (at most {MAX_FUNCTION_LINES}) "
                                 "with no comment above it saying why")
                i = end
        i += 1
    return found


def cycles(graph):
    found, state = [], {}

    def visit(node, stack):
        state[node] = "open"
        for target in graph.get(node, []):
            if state.get(target) == "open":
                found.append("include cycle: " + " -> ".join(stack[stack.index(target):] + [target]))
            elif target not in state:
                visit(target, stack + [target])
        state[node] = "done"

    for node in graph:
        if node not in state:
            visit(node, [node])
    return found


if __name__ == "__main__":
    sys.exit(main())
