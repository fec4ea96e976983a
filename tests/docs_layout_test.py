"""The layout table of docs/method.md against the source tree, and the layers' arrows.

    python3 tests/docs_layout_test.py SOURCE_DIR

1. Every row of the table whose first cell is a source folder names each
   header that folder holds (as `name.h`), and only headers it holds: a
   header added, moved or removed without the table fails here.
2. No file includes a header of a layer above its own
   (measure < io, registration < faces, terrain < tools): the layers of the
   table stay a graph without arrows back up.
"""
import os
import re
import sys

root = sys.argv[1] if len(sys.argv) > 1 else os.path.join(os.path.dirname(__file__), "..")
failures = []

# --- 1. the table ----------------------------------------------------------
text = open(os.path.join(root, "docs", "method.md"), encoding="utf-8").read()
rows = {}
for line in text.splitlines():
    m = re.match(r"\| `([a-z_/]+/)` \|[^|]*\|(.*)\|\s*$", line)
    if m:
        rows[m.group(1).rstrip("/")] = set(re.findall(r"`([A-Za-z0-9_]+\.h)`", m.group(2)))
layers = ("measure", "io", "registration", "faces", "terrain", "tools")
code_folders = [f for f in rows if f.split("/")[0] in layers and os.path.isdir(os.path.join(root, f))
                and any(n.endswith(".h") for n in os.listdir(os.path.join(root, f)))]
for folder in ["measure", "io", "registration", "faces", "terrain", "tools"]:
    if folder not in rows:
        failures.append("docs/method.md: the layout table has no row for `%s/`" % folder)
for folder in code_folders:
    present = {n for n in os.listdir(os.path.join(root, folder)) if n.endswith(".h")}
    for name in sorted(present - rows[folder]):
        failures.append("docs/method.md: the row `%s/` does not name %s/%s" % (folder, folder, name))
    for name in sorted(rows[folder] - present):
        failures.append("docs/method.md: the row `%s/` names %s, which is not in %s/"
                        % (folder, name, folder))
# Every folder with headers has a row.
for dirpath, dirnames, filenames in os.walk(root):
    rel = os.path.relpath(dirpath, root)
    top = rel.split(os.sep)[0]
    if top not in layers:
        continue
    if any(n.endswith(".h") for n in filenames) and rel.replace(os.sep, "/") not in rows:
        failures.append("docs/method.md: the layout table has no row for `%s/`" % rel)

# --- 2. the arrows -----------------------------------------------------------
rank = {"measure": 0, "io": 1, "registration": 1, "faces": 2, "terrain": 2, "tools": 3}
include = re.compile(r'^\s*#\s*include\s+"([a-z_]+)/', re.M)


def layer(path):
    """The layer a path (relative to the root, or an include's start) is in."""
    return path.replace(os.sep, "/").split("/")[0]


for top in rank:
    for dirpath, _, filenames in os.walk(os.path.join(root, top)):
        for name in filenames:
            if not name.endswith((".h", ".cc")):
                continue
            path = os.path.join(dirpath, name)
            own = layer(os.path.relpath(path, root))
            source = open(path, encoding="utf-8").read()
            for start in include.findall(source):
                target = layer(start)
                if target not in rank or target == own:
                    continue
                if rank[target] >= rank[own]:
                    failures.append("%s includes %s: a layer beside or above %s/"
                                    % (os.path.relpath(path, root), start, own))

for f in failures:
    print("FAIL " + f)
print("%d folders in the table checked, %d failures" % (len(code_folders), len(failures)))
sys.exit(1 if failures else 0)
