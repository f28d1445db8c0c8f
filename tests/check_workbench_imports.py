#!/usr/bin/env python3
"""The workbench's modules import each other without cycles (module-level imports; imports
inside functions are deferred on purpose and not counted), and a view provider module never
imports the feature module: a view provider asks its object.

usage: check_workbench_imports.py MOD_DIR      (exit 1 and the cycle or offence when found)
"""
import ast
import os
import sys


def module_imports(path, local):
    tree = ast.parse(open(path, encoding="utf-8").read(), path)
    found = set()
    for node in tree.body:  # module level only
        nodes = [node]
        if isinstance(node, (ast.If, ast.Try)):
            nodes = list(ast.walk(node))
        for n in nodes:
            if isinstance(n, ast.Import):
                found.update(a.name.split(".")[0] for a in n.names)
            elif isinstance(n, ast.ImportFrom) and n.module:
                found.add(n.module.split(".")[0])
    return found & local


def main(argv):
    mod = argv[1]
    files = {f[:-3]: os.path.join(mod, f) for f in os.listdir(mod) if f.endswith(".py")}
    local = set(files)
    graph = {m: module_imports(p, local) for m, p in files.items()}
    problems = []
    for m in graph:
        if "ViewProvider" in m and "FRepFeatures" in graph[m]:
            problems.append("%s imports FRepFeatures: a view provider asks its object" % m)
    # cycles, by depth-first search
    state = {}

    def visit(m, stack):
        state[m] = "active"
        for n in sorted(graph[m]):
            if state.get(n) == "active":
                problems.append("import cycle: " + " -> ".join(stack[stack.index(n):] + [n]))
            elif n not in state:
                visit(n, stack + [n])
        state[m] = "done"

    for m in sorted(graph):
        if m not in state:
            visit(m, [m])
    for p in problems:
        print(p)
    print("%d passed, %d failed" % (0 if problems else 1, len(problems)))
    return 1 if problems else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
