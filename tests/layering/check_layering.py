#!/usr/bin/env python3
"""Fails when the code's #include "seqtopo/X/..." lines contradict the module dependencies of src/CMakeLists.txt.

For every module M (seqtopo_add_module(M DEPS ...)):
  * each header or source of M (include/seqtopo/M/, src/M/) may include only M, core, and the modules M
    depends on, directly or through them;
  * each seqtopo module M declares directly is included by M somewhere (no dependency declared for nothing);
  * no module includes the command line or the Python bindings.
Also checks the tests' and benchmarks' include paths name modules that exist; that the tests of a module below
the job layer (tests/M/ for a module M that pipeline depends on) neither include nor link pipeline or outputs (a
test of a low module that needs the job layer belongs in tests/pipeline/); and that seqtopo-mpi (src/mpi/) does not
include the command line's sources (src/cli/): what both programs share lives outside either.
Usage: check_layering.py SOURCE_DIR
"""
import pathlib
import re
import sys

source = pathlib.Path(sys.argv[1] if len(sys.argv) > 1 else ".")
cmake = (source / "src" / "CMakeLists.txt").read_text()
# seqtopo_add_module(name [DEPS a b\n c ...]) possibly over several lines
declared = {}
for m in re.finditer(r"seqtopo_add_module\((\w+)((?:[^)])*)\)", cmake):
    name, rest = m.group(1), m.group(2)
    deps = re.findall(r"seqtopo::(\w+)", rest)
    declared[name] = set(deps)

def closure(name, seen=None):
    seen = set() if seen is None else seen
    for d in declared.get(name, ()):
        if d not in seen:
            seen.add(d)
            closure(d, seen)
    return seen

include_re = re.compile(r'^\s*#\s*include\s+"seqtopo/(\w+)/', re.M)
errors = []
for name in declared:
    allowed = closure(name) | {name, "core"}
    used = set()
    files = list((source / "include" / "seqtopo" / name).glob("**/*")) + list((source / "src" / name).glob("**/*"))
    for f in files:
        if f.suffix not in (".hpp", ".cpp", ".h"):
            continue
        for inc in include_re.findall(f.read_text()):
            used.add(inc)
            if inc not in declared:
                errors.append(f"{f.relative_to(source)}: includes seqtopo/{inc}/, which is not a module")
            elif inc not in allowed:
                errors.append(f"{f.relative_to(source)}: includes seqtopo/{inc}/ but module {name} does not depend on {inc}")
    for d in sorted(declared[name] - used):
        # A dependency may be needed only by what it brings in (e.g. core through another module): flag only those
        # that nothing of the module uses directly.
        errors.append(f"src/CMakeLists.txt: module {name} declares seqtopo::{d} but never includes seqtopo/{d}/")

for folder in ("tests", "bench", "python", "examples"):
    for f in (source / folder).glob("**/*"):
        if f.suffix in (".hpp", ".cpp") and "build" not in f.parts:
            for inc in include_re.findall(f.read_text()):
                if inc not in declared:
                    errors.append(f"{f.relative_to(source)}: includes seqtopo/{inc}/, which is not a module")

# Tests of a module below the job layer: no pipeline or outputs, in their includes or their LIBS.
job_layer = {"pipeline", "outputs"}
below = closure("pipeline") - job_layer
tests_cmake = (source / "tests" / "CMakeLists.txt").read_text()
for m in re.finditer(r"seqtopo_add_tests\((\w+)((?:[^)])*)\)", tests_cmake):
    name, rest = m.group(1), m.group(2)
    if name not in below:
        continue
    for lib in re.findall(r"seqtopo_(\w+)", rest):
        if lib in job_layer:
            errors.append(f"tests/CMakeLists.txt: the tests of module {name} link seqtopo_{lib} (the job layer)")
    for f in (source / "tests" / name).glob("**/*"):
        if f.suffix in (".hpp", ".cpp"):
            for inc in include_re.findall(f.read_text()):
                if inc in job_layer:
                    errors.append(f"{f.relative_to(source)}: a test of module {name} includes seqtopo/{inc}/ (the job layer)")

# seqtopo-mpi shares nothing with the command line's own sources.
cli_include_re = re.compile(r'^\s*#\s*include\s+"(?:\.\./)?cli/', re.M)
for f in (source / "src" / "mpi").glob("**/*"):
    if f.suffix in (".hpp", ".cpp") and cli_include_re.search(f.read_text()):
        errors.append(f"{f.relative_to(source)}: includes the command line's sources (src/cli/)")
if re.search(r"add_executable\(seqtopo-mpi[^)]*cli/", cmake):
    errors.append("src/CMakeLists.txt: seqtopo-mpi compiles the command line's sources (src/cli/)")

if errors:
    print("\n".join(errors))
    sys.exit(1)
print(f"layering: {len(declared)} modules, every include agrees with src/CMakeLists.txt")
