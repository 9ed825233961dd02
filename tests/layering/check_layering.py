#!/usr/bin/env python3
"""Checks the layering rules of docs/architecture.md against the sources and the CMake link lines.

  check_layering.py SOURCE_DIR      check the tree; one line per broken rule, exit 1 if any
  check_layering.py --self-test     break each rule in a copy of a tiny tree and check it is caught

The rules:
  1. a library includes only its own headers and those of the libraries it links (transitively),
     and private headers ("x.h") only from beside it; the support headers (<puff/support/...>)
     only from sources, never from a public header;
  2. bake never touches render (no link, no include of render, scene or eval);
  3. the render paths never include one another (a path's files include no other path's private
     files, and no other path's drawing library);
  4. no public header includes a GL header or Puff's private GL header;
  5. nothing a game links reaches eval, reference, bake, platform, puff_cli or the apps.
"""
import os
import re
import shutil
import sys
import tempfile

# Each library: its target, the folder of its public headers, the folders of its sources.
LIBRARIES = {
    "core": ("puff_core", "runtime/include/puff/core", ["runtime/src/core"]),
    "platform": ("puff_platform", "runtime/include/puff/platform", ["runtime/src/platform"]),
    "io": ("puff_io", "runtime/include/puff/io", ["runtime/src/io"]),
    "mesh": ("puff_mesh", "runtime/include/puff/mesh", ["runtime/src/mesh"]),
    "cel": ("puff_cel", "runtime/include/puff/cel", ["runtime/src/cel"]),
    "sim": ("puff_sim", "runtime/include/puff/sim", ["runtime/src/sim"]),
    "media": ("puff_media", "runtime/include/puff/media", ["runtime/src/media"]),
    "reference": ("puff_reference", "runtime/include/puff/reference", ["runtime/src/reference"]),
    "scene": ("puff_scene", "runtime/include/puff/scene", ["runtime/src/scene"]),
    "render": ("puff_render", "runtime/include/puff/render", ["runtime/src/render"]),
    "eval": ("puff_eval", "runtime/include/puff/eval", ["runtime/src/eval"]),
    "fixedfunc": ("puff_fixedfunc", "fixedfunc/include/puff/fixedfunc", ["fixedfunc/src/fixedfunc"]),
    "bake": ("puff_bake", "puffbake/include/puff/bake", ["puffbake/src/bake"]),
}
CMAKE_FILES = ["runtime/CMakeLists.txt", "fixedfunc/CMakeLists.txt", "puffbake/CMakeLists.txt"]
# What a game links: every installed library but these (docs/architecture.md, docs/embedding.md).
NOT_FOR_GAMES = {"puff_eval", "puff_reference", "puff_bake", "puff_platform", "puff_cli", "puffview_lib"}
# The render paths: each path's own files, and the drawing libraries only that path may include.
PATHS = {
    "cel": (["runtime/src/render/cel_path.cpp", "runtime/src/render/media_pass.cpp",
             "runtime/src/render/media_pass.h"], ["puff/cel/nailboards.h", "puff/cel/volume_clip.h",
                                                  "puff/media/layers.h"]),
    "fixed": (["runtime/src/render/fixed_path.cpp"], ["puff/fixedfunc/"]),
    "reference": (["runtime/src/eval/reference_path.cpp", "runtime/src/eval/cel_reference.cpp",
                   "runtime/src/eval/cel_reference_gl.h"], ["puff/eval/cel_reference.h", "puff/reference/"]),
}
GL_HEADER = re.compile(r'^\s*#\s*include\s*[<"](glad/|GL/|GLFW/|EGL/|puff/gl_api\.h|puff/glad)', re.M)
PUFF_INCLUDE = re.compile(r'^\s*#\s*include\s*<puff/(?!core/(?:error|random|number_text)\.h>)([a-z_]+)/', re.M)
# core's header-only values (Result and PUFF_CHECK, the seeded random numbers, numbers in messages), which puff::sim uses
# without linking any Puff library, are left out of rule 1 by PUFF_INCLUDE's look-ahead.
ANY_INCLUDE = re.compile(r'^\s*#\s*include\s*[<"]([^>"]+)[>"]', re.M)
LOCAL_INCLUDE = re.compile(r'^\s*#\s*include\s*"([^"]+)"', re.M)
LINK_CALL = re.compile(r'target_link_libraries\(\s*(\S+)([^)]*)\)', re.S)


def read(path):
    with open(path, encoding="utf-8") as f:
        return f.read()


def files_under(root, folder):
    out = []
    base = os.path.join(root, folder)
    for d, _, names in os.walk(base):
        out += [os.path.join(d, n) for n in sorted(names) if n.endswith((".h", ".cpp", ".inc"))]
    return out


def links(root):
    """target -> the Puff targets it links (PUBLIC, PRIVATE or INTERFACE alike)."""
    graph = {}
    for cm in CMAKE_FILES:
        text = re.sub(r"#[^\n]*", "", read(os.path.join(root, cm)))
        for target, rest in LINK_CALL.findall(text):
            deps = re.findall(r"\b(puff_[a-z_]+|puffview_lib)\b", rest)
            graph.setdefault(target, set()).update(d for d in deps if d not in ("puff_gl_api", "puff_support", "puff_glad"))
    return graph


def closure(graph, target):
    seen, todo = set(), [target]
    while todo:
        for d in graph.get(todo.pop(), ()):
            if d not in seen:
                seen.add(d)
                todo.append(d)
    return seen


def check(root):
    problems = []
    graph = links(root)
    target_of = {name: lib[0] for name, lib in LIBRARIES.items()}
    name_of = {t: n for n, t in target_of.items()}
    for name, (target, include_dir, src_dirs) in LIBRARIES.items():
        reach = {name_of[t] for t in closure(graph, target) if t in name_of} | {name}
        for public, folder in [(True, include_dir)] + [(False, s) for s in src_dirs]:
            for f in files_under(root, folder):
                rel = os.path.relpath(f, root)
                text = read(f)
                for lib in PUFF_INCLUDE.findall(text):
                    if lib == "support":
                        if public:
                            problems.append(f"{rel}: a public header includes <puff/support/...> (never installed)")
                    elif lib not in reach and lib in LIBRARIES:
                        problems.append(f"{rel}: includes <puff/{lib}/...> but {target} does not link puff_{lib}")
                for inc in LOCAL_INCLUDE.findall(text):
                    if "/" in inc or "\\" in inc:
                        problems.append(f"{rel}: includes \"{inc}\": a private header is named from beside it, never by a path")
                    elif not os.path.exists(os.path.join(os.path.dirname(f), inc)):
                        problems.append(f"{rel}: includes \"{inc}\", which is not beside it (another library's private header?)")
                if public and GL_HEADER.search(text):
                    problems.append(f"{rel}: a public header includes a GL header")
    # bake never touches render.
    bake_reach = closure(graph, "puff_bake") | closure(graph, "puffbake")
    for bad in ("puff_render", "puff_scene", "puff_eval"):
        if bad in bake_reach:
            problems.append(f"puffbake: puff_bake or puffbake links {bad} (bake never touches render)")
    for folder in ("puffbake",):
        for f in files_under(root, folder):
            for lib in PUFF_INCLUDE.findall(read(f)):
                if lib in ("render", "scene", "eval"):
                    problems.append(f"{os.path.relpath(f, root)}: includes <puff/{lib}/...> (bake never touches render)")
    # The render paths never include one another.
    for path, (own, libs) in PATHS.items():
        for other, (other_own, other_libs) in PATHS.items():
            if other == path:
                continue
            for f in own:
                full = os.path.join(root, f)
                if not os.path.exists(full):
                    problems.append(f"{f}: listed as a file of the {path} path but missing (update PATHS)")
                    continue
                for inc in ANY_INCLUDE.findall(read(full)):
                    if any(os.path.basename(o) == os.path.basename(inc) for o in other_own) or \
                       any(inc.startswith(lib) for lib in other_libs):
                        problems.append(f"{f}: the {path} path includes {inc}, the {other} path's")
    # Nothing a game links reaches what games never need.
    for name, (target, _, _) in LIBRARIES.items():
        if target in NOT_FOR_GAMES:
            continue
        for bad in sorted(closure(graph, target) & NOT_FOR_GAMES):
            problems.append(f"{target}: links {bad}, which a game never needs")
    return problems


def self_test():
    """Each rule broken once in a copy of the real tree must be reported."""
    here = os.path.dirname(os.path.abspath(__file__))
    root = os.path.abspath(os.path.join(here, "..", ".."))
    breaks = [
        ("runtime/include/puff/cel/types.h", "#include <GL/gl.h>\n", "GL header"),
        ("runtime/include/puff/core/error.h", "#include <puff/support/text.h>\n", "<puff/support/"),
        ("runtime/src/sim/forces.cpp", "#include <puff/render/render.h>\n", "does not link puff_render"),
        ("runtime/src/core/gl.cpp", '#include "gl_backends.h"\n', "not beside it"),
        ("runtime/src/cel/frame.cpp", '#include "../render/target.h"\n', "never by a path"),
        ("puffbake/src/bake/layout.cpp", "#include <puff/render/render.h>\n", "bake never touches render"),
        ("runtime/src/render/fixed_path.cpp", '#include "media_pass.h"\n', "the cel path's"),
        ("runtime/src/render/cel_path.cpp", "#include <puff/fixedfunc/renderer.h>\n", "the fixed path's"),
        ("runtime/CMakeLists.txt", "target_link_libraries(puff_cel PUBLIC puff_platform)\n", "which a game never needs"),
    ]
    failed = 0
    if check(root):
        print("self-test: the tree itself breaks a rule; run the check first", file=sys.stderr)
        return 1
    for rel, line, expect in breaks:
        with tempfile.TemporaryDirectory() as tmp:
            for top in ("runtime", "fixedfunc", "puffbake"):
                shutil.copytree(os.path.join(root, top), os.path.join(tmp, top),
                                ignore=shutil.ignore_patterns("examples", "*.png", "*.json"))
            with open(os.path.join(tmp, rel), "a", encoding="utf-8") as f:
                f.write(line)
            found = [p for p in check(tmp) if expect in p]
            if not found:
                print(f"self-test: {rel} + {line.strip()!r} was not reported", file=sys.stderr)
                failed += 1
    print(f"self-test: {len(breaks) - failed} of {len(breaks)} broken rules reported")
    return 1 if failed else 0


def main(argv):
    if argv[1:] == ["--self-test"]:
        return self_test()
    if len(argv) != 2:
        print(__doc__.strip(), file=sys.stderr)
        return 2
    problems = check(argv[1])
    for p in problems:
        print(f"layering: {p}", file=sys.stderr)
    print(f"layering: {len(LIBRARIES)} libraries checked, {len(problems)} broken rule(s)")
    return 1 if problems else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
