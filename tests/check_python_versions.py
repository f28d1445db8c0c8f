#!/usr/bin/env python3
"""No file of the project names a Python minor version: FRepCAD is built for the Python that
FreeCAD runs (3.x on one distribution, another 3.y on the next; cmake/FreeCADPython.cmake
finds it), so an interpreter path, a version pin or an ABI tag written into a file breaks
the other platform.

usage: check_python_versions.py SOURCE_DIR              (exit 1 and each offence when found)
       check_python_versions.py --self-test SOURCE_DIR  (the check catches planted offences)
"""
import os
import re
import subprocess
import sys
import tempfile

# An interpreter or library name with its minor version (python3.N, libpython3.N,
# /usr/include/python3.N), an ABI tag (cpython-3NN), a CMake version pin
# (find_package(Python 3.N ...)) or prose naming one (Python 3.N), N a number.
PATTERN = re.compile(r"python3\.\d+|cpython-3\d+|find_package\s*\(\s*Python3?\s+3\.\d+"
                     r"|\bPython\s+3\.\d+", re.IGNORECASE)
SKIP_SUFFIXES = (".png", ".jpg", ".FCStd", ".stl", ".3mf", ".vdb", ".bms", ".gz", ".so")


def project_files(root):
    try:
        out = subprocess.run(["git", "-C", root, "ls-files", "-z", "--cached", "--others",
                              "--exclude-standard"], check=True, capture_output=True).stdout
        return [f for f in out.decode().split("\0") if f]
    except (OSError, subprocess.CalledProcessError):  # not a git checkout: every file
        files = []
        for d, dirs, names in os.walk(root):
            dirs[:] = [x for x in dirs if x not in (".git", "build")]
            files += [os.path.relpath(os.path.join(d, n), root) for n in names]
        return files


def offences(root):
    found = []
    for rel in project_files(root):
        path = os.path.join(root, rel)
        if rel.endswith(SKIP_SUFFIXES) or not os.path.isfile(path):
            continue
        with open(path, "rb") as f:
            data = f.read()
        if b"\0" in data[:4096]:
            continue  # binary
        for n, line in enumerate(data.decode("utf-8", "replace").splitlines(), 1):
            for m in PATTERN.finditer(line):
                found.append("%s:%d: names a Python minor version: %r" % (rel, n, m.group(0)))
    return found


def self_test():
    with tempfile.TemporaryDirectory() as root:
        minor = "3." + "11"  # (spelt apart, so that this file does not name one itself)
        planted = {"CMakeLists.txt": "find_package(Python %s EXACT REQUIRED)\n" % minor,
                   "run.sh": "exec /usr/bin/python%s -m pytest\n" % minor,
                   "notes.md": "Built against Python %s only.\n" % minor,
                   "clean.py": "#!/usr/bin/env python3\nimport sys  # python3 and Python 3\n"}
        for name, text in planted.items():
            with open(os.path.join(root, name), "w") as f:
                f.write(text)
        found = offences(root)
        expected = ["CMakeLists.txt:1", "run.sh:1", "notes.md:1"]
        missing = [e for e in expected if not any(f.startswith(e) for f in found)]
        wrong = [f for f in found if f.startswith("clean.py")]
        if missing or wrong:
            print("check_python_versions self-test FAILED: missed %s, wrongly flagged %s"
                  % (missing, wrong))
            return 1
    print("check_python_versions self-test: the planted offences were caught")
    return 0


def main(argv):
    if len(argv) == 3 and argv[1] == "--self-test":
        return self_test()
    found = offences(argv[1])
    for f in found:
        print(f)
    if found:
        return 1
    print("check_python_versions: no file names a Python minor version")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
