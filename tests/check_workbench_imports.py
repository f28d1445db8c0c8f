#!/usr/bin/env python3
"""The workbench's modules import each other one way: no import cycle, counting every import
(at module level and inside functions alike), and no view module (a view provider, a panel, a
dragger) imports a feature module (one that defines a document feature's proxy): a view asks
its object (obj.Proxy) for what it needs.

usage: check_workbench_imports.py MOD_DIR              (exit 1 with each cycle or offence)
       check_workbench_imports.py --self-test MOD_DIR  (a copy with a cycle and a view that
                                                        imports a feature must fail)
"""
import ast
import os
import shutil
import sys
import tempfile

VIEW_WORDS = ("View", "Panel", "Dragger")


def parse(path):
    with open(path, encoding="utf-8") as f:
        return ast.parse(f.read(), path)


def imports_of(tree, local):
    """The workbench modules a module imports anywhere in it."""
    found = set()
    for node in ast.walk(tree):
        if isinstance(node, ast.Import):
            found.update(a.name.split(".")[0] for a in node.names)
        elif isinstance(node, ast.ImportFrom) and node.module and node.level == 0:
            found.add(node.module.split(".")[0])
    return found & local


def defines_feature(tree):
    """Whether the module defines a document feature's proxy (a FeatureProxy subclass)."""
    for node in ast.walk(tree):
        if isinstance(node, ast.ClassDef):
            for base in node.bases:
                name = base.attr if isinstance(base, ast.Attribute) else getattr(base, "id", "")
                if name == "FeatureProxy":
                    return True
    return False


def problems_in(mod):
    files = {f[:-3]: os.path.join(mod, f) for f in os.listdir(mod) if f.endswith(".py")}
    local = set(files)
    trees = {m: parse(p) for m, p in files.items()}
    graph = {m: imports_of(t, local) - {m} for m, t in trees.items()}
    features = {m for m, t in trees.items() if defines_feature(t)}
    views = {m for m in files if any(w in m for w in VIEW_WORDS)}
    problems = []
    for m in sorted(views):
        for f in sorted(graph[m] & features):
            problems.append("%s (a view module) imports %s (a feature module): ask the object "
                            "(obj.Proxy) instead" % (m, f))
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
    return problems, features, views


def self_test(mod):
    """A copy of the workbench with a cycle made by an import inside a function, and a view
    module importing a feature module inside a function, must be refused for both."""
    failures = []
    with tempfile.TemporaryDirectory() as tmp:
        copy = os.path.join(tmp, "FRep")
        shutil.copytree(mod, copy)
        problems, features, views = problems_in(copy)
        if problems:
            failures.append("the workbench itself fails: %s" % problems)
        if not features or not views:
            failures.append("no feature or no view module found (%s, %s)" % (features, views))
        with open(os.path.join(copy, "FRepPaths.py"), "a", encoding="utf-8") as f:
            f.write("\n\ndef _late():\n    import FRepCommands\n    return FRepCommands\n")
        view, feature = sorted(views)[0], sorted(features)[0]
        with open(os.path.join(copy, view + ".py"), "a", encoding="utf-8") as f:
            f.write("\n\ndef _late_feature():\n    from %s import *  # noqa\n" % feature)
        problems, _, _ = problems_in(copy)
        for p in problems:
            print("found, as it should: " + p)
        if not any(p.startswith("import cycle:") and "FRepPaths" in p for p in problems):
            failures.append("a cycle through an import inside a function was not found")
        if not any(p.startswith("%s (a view module) imports %s" % (view, feature))
                   for p in problems):
            failures.append("%s importing %s inside a function was not found" % (view, feature))
    for f in failures:
        print("FAIL: " + f)
    print("%d passed, %d failed" % (2 - min(2, len(failures)), len(failures)))
    return 1 if failures else 0


def main(argv):
    if argv[1] == "--self-test":
        return self_test(argv[2])
    problems, _, _ = problems_in(argv[1])
    for p in problems:
        print(p)
    print("%d passed, %d failed" % (0 if problems else 1, len(problems)))
    return 1 if problems else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
