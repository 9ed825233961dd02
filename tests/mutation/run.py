#!/usr/bin/env python3
"""Mutation testing: does the suite see a one-line change to the renderer?

Each mutant in tests/mutation/mutants.json replaces one exact piece of text (it must occur exactly
once) in a shader or a C++ source. Shader mutants are applied to a copy of shaders/ that
puff_tests reads through PUFF_SHADER_DIR: nothing in the tree changes and nothing is rebuilt.
C++ mutants are applied to the source in place, puff_tests is rebuilt, and the file is restored
(and puff_tests rebuilt once more) whatever happens; run them only from a clean tree.

A mutant is killed by a test that passes on the unmutated tree (the baseline, run first with the
same filters) and fails, crashes or times out with the mutant. Kills are split into golden-image
tests and the rest (analytic tests); the goal is that every mutant is killed by an analytic test.

  python3 tests/mutation/run.py --build build              # every mutant
  python3 tests/mutation/run.py --build build --only eq2-world-light,ink-width-plus-one
  python3 tests/mutation/run.py --list

Writes OUT/mutants.csv and OUT/report.md (OUT defaults to BUILD/mutation) and prints the score.
Not part of CI (docs/testing.md says how long it takes).
"""
import argparse
import csv
import json
import os
import re
import shutil
import signal
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
GOLDEN = re.compile(r"Golden")  # ArtScenes/SceneGolden, MediaSceneGolden, AnimatedSceneGolden
CWD = None
ALWAYS_EXCLUDED = ["ShaderEmbedded.*"]  # fails by design whenever PUFF_SHADER_DIR is set


def load(path):
    with open(path) as f:
        spec = json.load(f)
    seen = set()
    for m in spec["mutants"]:
        for key in ("id", "file", "find", "replace", "suites", "what"):
            if key not in m:
                sys.exit(f"{path}: mutant {m.get('id', '?')} has no '{key}'")
        if m["id"] in seen:
            sys.exit(f"{path}: mutant id {m['id']} appears twice")
        seen.add(m["id"])
        for s in m["suites"]:
            if s not in spec["suites"]:
                sys.exit(f"{path}: mutant {m['id']} names suite group '{s}', which is not in 'suites'")
    return spec


def mutate_text(text, m, path):
    count = text.count(m["find"])
    if count != 1:
        raise ValueError(f"{path}: mutant {m['id']}: the text to replace occurs {count} times (must be once)")
    return text.replace(m["find"], m["replace"])


def gtest_filter(spec, groups):
    """The union of the groups' positive patterns, less every group's negative patterns (gtest's
    POSITIVE-NEGATIVE syntax) and the tests that cannot run against a shader directory."""
    pos, neg = [], list(ALWAYS_EXCLUDED)
    for g in groups:
        p, _, n = spec["suites"][g].partition("-")
        for pat in p.split(":"):
            if pat and pat not in pos:
                pos.append(pat)
        for pat in n.split(":"):
            if pat and pat not in neg:
                neg.append(pat)
    return ":".join(pos) + "-" + ":".join(neg)


def run_tests(exe, flt, shader_dir, timeout, workdir):
    """Returns ({test: 'pass'|'fail'}, note). A crash or timeout marks every test without a result."""
    out = Path(workdir) / "result.json"
    if out.exists():
        out.unlink()
    env = dict(os.environ, PUFF_GL=os.environ.get("PUFF_GL", "osmesa"))
    # A mutant's failing goldens write their images here, not where tests/golden/accept.sh looks.
    env["PUFF_GOLDEN_OUTPUT_DIR"] = str(Path(workdir) / "golden-out")
    if shader_dir:
        env["PUFF_SHADER_DIR"] = str(shader_dir)
    else:
        env.pop("PUFF_SHADER_DIR", None)
    cmd = [str(exe), f"--gtest_filter={flt}", f"--gtest_output=json:{out}"]
    note = ""
    try:
        p = subprocess.run(cmd, env=env, cwd=CWD, stdout=subprocess.PIPE, stderr=subprocess.STDOUT,
                           timeout=timeout, text=True, errors="replace")
        if p.returncode not in (0, 1):
            note = f"exit {p.returncode}"
        log = p.stdout
    except subprocess.TimeoutExpired as e:
        note = f"timed out after {timeout} s"
        log = e.stdout.decode(errors="replace") if isinstance(e.stdout, bytes) else (e.stdout or "")
    results = {}
    if out.exists():
        try:
            data = json.loads(out.read_text())
            for suite in data.get("testsuites", []):
                for t in suite.get("testsuite", []):
                    name = f"{suite['name']}.{t['name']}"
                    if t.get("result") == "SKIPPED" or t.get("status") == "NOTRUN":
                        results[name] = "skip"
                    else:
                        results[name] = "fail" if t.get("failures") else "pass"
        except (json.JSONDecodeError, KeyError) as e:
            note += f" (unreadable result: {e})"
    else:
        # No JSON: the process died. Tests it ran and reported as OK in its log passed.
        for name in re.findall(r"^\[       OK \] (\S+)", log, re.M):
            results[name] = "pass"
        note = note or "no result file"
    return results, note, log


class Restore:
    """Puts C++ sources back on exit, SIGINT and SIGTERM included."""

    def __init__(self):
        self.saved = {}

    def save(self, path):
        self.saved.setdefault(path, path.read_bytes())

    def restore(self):
        for path, data in self.saved.items():
            path.write_bytes(data)
        changed = bool(self.saved)
        self.saved = {}
        return changed


def build(build_dir):
    p = subprocess.run(["cmake", "--build", str(build_dir), "--target", "puff_tests", "-j", str(os.cpu_count() or 2)],
                       stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True, errors="replace")
    return p.returncode == 0, p.stdout[-3000:]


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--build", default="build", help="the build directory (holds tests/puff_tests)")
    ap.add_argument("--mutants", default=str(ROOT / "tests/mutation/mutants.json"))
    ap.add_argument("--only", default="", help="comma-separated mutant ids")
    ap.add_argument("--out", default="", help="where mutants.csv and report.md go (default BUILD/mutation)")
    ap.add_argument("--timeout", type=int, default=1200, help="seconds per run of the tests")
    ap.add_argument("--list", action="store_true", help="list the mutants and exit")
    ap.add_argument("--keep-going", action="store_true", help="record a mutant that does not apply and go on")
    ap.add_argument("--shaders-only", action="store_true", help="only the shader mutants (nothing is rebuilt)")
    ap.add_argument("--exe", default="", help="the puff_tests to run (default BUILD/tests/puff_tests); a copy "
                    "keeps a run going while the build changes (shader mutants only)")
    args = ap.parse_args()

    spec = load(args.mutants)
    mutants = spec["mutants"]
    if args.only:
        want = args.only.split(",")
        unknown = [w for w in want if w not in {m["id"] for m in mutants}]
        if unknown:
            sys.exit(f"unknown mutant ids: {', '.join(unknown)}")
        mutants = [m for m in mutants if m["id"] in want]
    if args.shaders_only:
        mutants = [m for m in mutants if m["file"].startswith("shaders/")]
    if args.list:
        for m in mutants:
            print(f"{m['id']:32} {m['file']:40} {m['what']}")
        return 0

    build_dir = Path(args.build).resolve()
    global CWD
    CWD = build_dir / "tests"  # where ctest runs puff_tests
    exe = Path(args.exe).resolve() if args.exe else build_dir / "tests" / "puff_tests"
    if args.exe and any(not m["file"].startswith("shaders/") for m in mutants):
        sys.exit("--exe runs shader mutants only (C++ mutants rebuild BUILD's puff_tests): add --shaders-only")
    if not exe.exists():
        sys.exit(f"{exe}: not found (build the tree first: cmake --build {args.build})")
    out_dir = Path(args.out).resolve() if args.out else build_dir / "mutation"
    out_dir.mkdir(parents=True, exist_ok=True)

    # Every mutant applies before anything runs (a stale mutant is an error in the list, not a kill).
    problems = []
    for m in mutants:
        path = ROOT / m["file"]
        try:
            mutate_text(path.read_text(), m, m["file"])
        except (OSError, ValueError) as e:
            problems.append(str(e))
    if problems and not args.keep_going:
        print("\n".join(problems), file=sys.stderr)
        return 2

    restore = Restore()

    def on_signal(signum, frame):
        if restore.restore():
            print("restored the C++ sources; rebuild puff_tests before using it", file=sys.stderr)
        sys.exit(128 + signum)

    signal.signal(signal.SIGINT, on_signal)
    signal.signal(signal.SIGTERM, on_signal)

    work = Path(tempfile.mkdtemp(prefix="puff-mutation-"))
    rows = []
    try:
        # The baseline, once per filter: tests that fail unmutated cannot kill anything.
        baselines = {}
        groups_needed = sorted({tuple(m["suites"]) for m in mutants})
        t0 = time.time()
        pristine = work / "pristine-shaders"  # the baseline reads shaders as the mutants do
        shutil.copytree(ROOT / "shaders", pristine)
        for groups in groups_needed:
            flt = gtest_filter(spec, groups)
            res, note, _ = run_tests(exe, flt, pristine, args.timeout, work)
            if not res:
                sys.exit(f"baseline for {'+'.join(groups)} ran no test ({note}); filter {flt}")
            bad = [t for t, r in res.items() if r == "fail"]
            print(f"baseline {'+'.join(groups)}: {len(res)} tests, {len(bad)} failing unmutated"
                  f"{' (' + ', '.join(bad) + ')' if bad else ''}, {time.time() - t0:.0f} s", flush=True)
            baselines[groups] = res
            t0 = time.time()

        for i, m in enumerate(mutants, 1):
            t0 = time.time()
            groups = tuple(m["suites"])
            base = baselines[groups]
            path = ROOT / m["file"]
            status, note, killers = "", "", []
            try:
                mutated = mutate_text(path.read_text(), m, m["file"])
            except (OSError, ValueError) as e:
                rows.append(dict(m, status="does not apply", note=str(e), analytic=[], golden=[], seconds=0))
                print(f"[{i}/{len(mutants)}] {m['id']}: does not apply: {e}", flush=True)
                continue
            shader_dir = None
            if m["file"].startswith("shaders/"):
                shader_dir = work / "shaders"
                if shader_dir.exists():
                    shutil.rmtree(shader_dir)
                shutil.copytree(ROOT / "shaders", shader_dir)
                (shader_dir / Path(m["file"]).relative_to("shaders")).write_text(mutated)
            else:
                restore.save(path)
                path.write_text(mutated)
                ok, log = build(build_dir)
                if not ok:
                    restore.restore()
                    rows.append(dict(m, status="does not build", note=log.splitlines()[-1] if log else "",
                                     analytic=[], golden=[], seconds=round(time.time() - t0)))
                    print(f"[{i}/{len(mutants)}] {m['id']}: does not build", flush=True)
                    continue
            res, note, _ = run_tests(exe, gtest_filter(spec, groups), shader_dir, args.timeout, work)
            if restore.restore():
                ok, log = build(build_dir)
                if not ok:
                    sys.exit(f"puff_tests does not build after restoring {m['file']}:\n{log}")
            for t, r in base.items():
                if r != "pass":
                    continue
                after = res.get(t)
                if after == "fail" or (after is None and note):  # failed, or died before reporting
                    killers.append(t)
            analytic = [t for t in killers if not GOLDEN.search(t)]
            golden = [t for t in killers if GOLDEN.search(t)]
            status = "killed" if analytic else ("golden only" if golden else "survived")
            if note and not killers:
                status = "error"
            secs = round(time.time() - t0)
            rows.append(dict(m, status=status, note=note, analytic=analytic, golden=golden, seconds=secs))
            print(f"[{i}/{len(mutants)}] {m['id']}: {status} ({len(analytic)} analytic, {len(golden)} golden"
                  f"{'; ' + note if note else ''}) {secs} s", flush=True)
    finally:
        if restore.restore():
            build(build_dir)
        shutil.rmtree(work, ignore_errors=True)

    with open(out_dir / "mutants.csv", "w", newline="") as f:
        w = csv.writer(f)
        w.writerow(["id", "area", "file", "status", "analytic_kills", "golden_kills", "seconds", "killed_by", "note"])
        for r in rows:
            w.writerow([r["id"], r.get("area", ""), r["file"], r["status"], len(r["analytic"]), len(r["golden"]),
                        r["seconds"], " ".join(r["analytic"] + r["golden"]), r["note"]])
    killed = sum(r["status"] == "killed" for r in rows)
    golden_only = sum(r["status"] == "golden only" for r in rows)
    survived = [r["id"] for r in rows if r["status"] not in ("killed", "golden only")]
    with open(out_dir / "report.md", "w") as f:
        f.write(f"# Mutation score: {killed} of {len(rows)} mutants killed by an analytic test\n\n")
        f.write(f"{golden_only} killed by golden images alone; not killed: {', '.join(survived) or 'none'}.\n\n")
        f.write("| mutant | area | what | status | analytic tests that kill it | goldens |\n|---|---|---|---|---|---|\n")
        for r in rows:
            a = ", ".join(r["analytic"][:4]) + (f" (+{len(r['analytic']) - 4})" if len(r["analytic"]) > 4 else "")
            f.write(f"| {r['id']} | {r.get('area', '')} | {r['what']} | {r['status']} | {a} | {len(r['golden'])} |\n")
    print(f"\nscore: {killed}/{len(rows)} killed by an analytic test; {golden_only} by goldens alone; "
          f"not killed: {', '.join(survived) or 'none'}")
    print(f"wrote {out_dir / 'mutants.csv'} and {out_dir / 'report.md'}")
    return 0 if not survived and not golden_only else 1


if __name__ == "__main__":
    sys.exit(main())
