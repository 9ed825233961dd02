#!/usr/bin/env python3
"""Mutation testing: does the suite see a one-line change to the renderer?

Each mutant in tests/mutation/mutants.json replaces one exact piece of text (it must occur exactly
once) in a shader or a C++ source, and names the groups of tests (gtest filters) to run against it.

  The tests are the tiers' executables, puff_tests_* (tests/tiers.cmake): each group's filter runs
  in every one of them, so a group may span the tiers.
  Shader mutants are applied to a copy of shaders/ that the tests read through PUFF_SHADER_DIR:
  nothing in the tree changes and nothing is rebuilt.
  C++ mutants are applied to the source in place and the tests (with the tools: puffbake,
  puffrender, puffview) are rebuilt; the source is put back
  (and the tests rebuilt) when the mutant is done, and on Ctrl-C, SIGTERM or SIGHUP. They need a
  tree whose mutated files have no uncommitted changes, and the tests are built before the baseline.

First each group runs once unmutated (the baseline; every run reads the shaders from a copy, with
PUFF_CI=1 so that a test which cannot run fails rather than skips). A mutant is killed by a test
that passes in the baseline and fails with the mutant, or crashes or times out while it runs (tests
that never ran after a crash kill nothing). Kills by the art scenes' golden images
(ArtScenes/*SceneGolden) are counted apart from the rest, the analytic tests: the goal is that
every mutant is killed by an analytic test. Mutants that do not apply, do not build, or whose run
went wrong without a kill are listed apart and left out of the score.

  python3 tests/mutation/run.py --build build                        # every mutant
  python3 tests/mutation/run.py --build build --only eq2-world-light,ink-wider-1px
  python3 tests/mutation/run.py --build build --shaders-only --exe /tmp/puff-tests-copy
  python3 tests/mutation/run.py --list

Writes OUT/mutants.csv and OUT/report.md (OUT: --out, default BUILD/mutation), also when stopped
early, and prints the score. Exit status: 0 every mutant killed by an analytic test, 1 some not,
2 the run could not be made (bad arguments, a stale mutant, a failing build or baseline).
Not part of CI: docs/testing.md says how long it takes.
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
GOLDEN = re.compile(r"^ArtScenes/\w*SceneGolden\.")  # the art scenes' golden images
# Fail by design whenever PUFF_SHADER_DIR is set (the embedded copy differs), or test the golden
# comparator itself, which no renderer mutant reaches.
ALWAYS_EXCLUDED = ["ShaderEmbedded.*", "Golden.*"]


class SetupError(Exception):
    pass


def load(path):
    try:
        with open(path) as f:
            spec = json.load(f)
    except (OSError, json.JSONDecodeError) as e:
        raise SetupError(f"{path}: {e}")
    seen = set()
    for m in spec.get("mutants", []):
        for key in ("id", "file", "find", "replace", "suites", "what"):
            if key not in m:
                raise SetupError(f"{path}: mutant {m.get('id', '?')} has no '{key}'")
        if m["id"] in seen:
            raise SetupError(f"{path}: mutant id {m['id']} appears twice")
        seen.add(m["id"])
        for s in m["suites"]:
            if s not in spec.get("suites", {}):
                raise SetupError(f"{path}: mutant {m['id']} names suite group '{s}', which is not in 'suites'")
    return spec


def mutate_text(text, m):
    count = text.count(m["find"])
    if count != 1:
        raise ValueError(f"{m['file']}: mutant {m['id']}: the text to replace occurs {count} times (must be once)")
    return text.replace(m["find"], m["replace"])


def gtest_filter(pattern):
    """One group's filter (gtest's POSITIVE-NEGATIVE; an empty positive part is '*'), less the
    tests that are never run here."""
    pos, _, neg = pattern.partition("-")
    negatives = [p for p in neg.split(":") if p] + ALWAYS_EXCLUDED
    return (pos or "*") + "-" + ":".join(negatives)


def parse_log(log):
    """Results from gtest's console output (when it died before writing its JSON): tests it reported,
    and the one it was running when it died."""
    results = {}
    running = None
    for line in log.splitlines():
        m = re.match(r"^\[ RUN      \] (\S+)", line)
        if m:
            running = m.group(1)
            continue
        m = re.match(r"^\[\s+(OK|FAILED|SKIPPED)\s+\] (\S+) \(", line)
        if m:
            results[m.group(2)] = {"OK": "pass", "FAILED": "fail", "SKIPPED": "skip"}[m.group(1)]
            if m.group(2) == running:
                running = None
    return results, running


def run_one(exe, pattern, shader_dir, timeout, workdir, cwd):
    """Runs one group in one executable. Returns ({test: 'pass'|'fail'|'skip'}, note, log); a test that crashed or
    timed out is 'fail', tests that never ran are absent."""
    out = Path(workdir) / "result.json"
    if out.exists():
        out.unlink()
    env = dict(os.environ, PUFF_GL=os.environ.get("PUFF_GL", "osmesa"), PUFF_CI="1",
               PUFF_SHADER_DIR=str(shader_dir),
               # A mutant's failing goldens write here, not where tests/golden/accept.sh looks.
               PUFF_GOLDEN_OUTPUT_DIR=str(Path(workdir) / "golden-out"))
    cmd = [str(exe), f"--gtest_filter={gtest_filter(pattern)}", f"--gtest_output=json:{out}"]
    # Tests that open a window (puffview's) need a display: a private Xvfb, as ctest gives them.
    if not os.environ.get("DISPLAY") and shutil.which("Xvfb"):
        cmd = [str(ROOT / "tests" / "support" / "with_xvfb.sh")] + cmd
    note = ""
    try:
        p = subprocess.run(cmd, env=env, cwd=cwd, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, timeout=timeout,
                           text=True, errors="replace")
        log = p.stdout
        if p.returncode not in (0, 1):
            note = f"exit status {p.returncode}"
    except subprocess.TimeoutExpired as e:
        log = e.stdout.decode(errors="replace") if isinstance(e.stdout, bytes) else (e.stdout or "")
        note = f"timed out after {timeout} s"
    results = {}
    if not note and out.exists():
        try:
            data = json.loads(out.read_text())
            for suite in data.get("testsuites", []):
                for t in suite.get("testsuite", []):
                    name = f"{suite['name']}.{t['name']}"
                    if t.get("result") == "SKIPPED":
                        results[name] = "skip"
                    else:
                        results[name] = "fail" if t.get("failures") else "pass"
            return results, note, log
        except (json.JSONDecodeError, KeyError) as e:
            note = f"unreadable test results ({e})"
    results, running = parse_log(log)
    note = note or "no test results written"
    if running:
        results[running] = "fail"
        note += f", in {running}"
    return results, note, log


def test_executables(exe_dir):
    """The tiers' test executables in exe_dir (puff_tests_TIER, tests/tiers.cmake)."""
    return sorted(p for p in Path(exe_dir).glob("puff_tests_*") if p.is_file() and os.access(p, os.X_OK))


def run_tests(exes, pattern, shader_dir, timeout, workdir, cwd):
    """Runs one group in every executable: the union of their results, and their notes and logs."""
    results, notes, logs = {}, [], []
    for exe in exes:
        res, note, log = run_one(exe, pattern, shader_dir, timeout, workdir, cwd)
        results.update(res)
        if note:
            notes.append(f"{exe.name}: {note}")
        logs.append(log)
    return results, "; ".join(notes), "\n".join(logs)


def build(build_dir):
    # The tests run the tools too (puffbake, puffrender, puffview): a mutant in a tool's code is
    # built into it as well as into the tests.
    targets = [p.name for p in test_executables(Path(build_dir) / "tests")] + ["puffbake", "puffrender"]
    if (Path(build_dir) / "runtime" / "puffview").exists():
        targets.append("puffview")
    p = subprocess.run(["cmake", "--build", str(build_dir), "--target", *targets, "-j", str(os.cpu_count() or 2)],
                       stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True, errors="replace")
    return p.returncode == 0, p.stdout[-3000:]


def write_atomically(path, text):
    tmp = path.with_name(path.name + ".mutation-tmp")
    tmp.write_text(text)
    os.replace(tmp, path)


def interrupt(signum, frame):
    raise KeyboardInterrupt(f"signal {signum}")


def write_reports(out_dir, rows, baselines, interrupted):
    out_dir.mkdir(parents=True, exist_ok=True)
    with open(out_dir / "mutants.csv", "w", newline="") as f:
        w = csv.writer(f)
        w.writerow(["id", "area", "file", "status", "analytic_kills", "golden_kills", "seconds", "killed_by", "note"])
        for r in rows:
            w.writerow([r["id"], r.get("area", ""), r["file"], r["status"], len(r["analytic"]), len(r["golden"]),
                        r["seconds"], " ".join(r["analytic"] + r["golden"]), r["note"]])
    scored = [r for r in rows if r["status"] in ("killed", "golden only", "survived")]
    killed = [r["id"] for r in scored if r["status"] == "killed"]
    golden_only = [r["id"] for r in scored if r["status"] == "golden only"]
    survived = [r["id"] for r in scored if r["status"] == "survived"]
    apart = [r for r in rows if r not in scored]
    with open(out_dir / "report.md", "w") as f:
        f.write(f"# Mutation score: {len(killed)} of {len(scored)} mutants killed by an analytic test\n\n")
        if interrupted:
            f.write("**Stopped early: these are the mutants run so far.**\n\n")
        f.write(f"Killed by golden images alone: {', '.join(golden_only) or 'none'}. "
                f"Not killed: {', '.join(survived) or 'none'}.\n\n")
        if apart:
            f.write("Left out of the score: " + "; ".join(f"{r['id']} ({r['status']}: {r['note']})" for r in apart) +
                    ".\n\n")
        for group, res in baselines.items():
            bad = sorted(t for t, v in res.items() if v != "pass")
            f.write(f"Baseline `{group}`: {len(res)} tests; not passing unmutated (cannot kill): "
                    f"{', '.join(bad) or 'none'}.\n\n")
        f.write("| mutant | area | what | status | analytic tests that kill it | goldens | note |\n"
                "|---|---|---|---|---|---|---|\n")
        for r in rows:
            a = ", ".join(r["analytic"][:4]) + (f" (+{len(r['analytic']) - 4})" if len(r["analytic"]) > 4 else "")
            f.write(f"| {r['id']} | {r.get('area', '')} | {r['what']} | {r['status']} | {a} | {len(r['golden'])} "
                    f"| {r['note']} |\n")
    return killed, golden_only, survived, scored, apart


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--build", default="build",
                    help="the build directory holding tests/puff_tests_*, relative to the current directory "
                         "(default: %(default)s)")
    ap.add_argument("--mutants", default=str(ROOT / "tests/mutation/mutants.json"),
                    help="the mutant list (default: the repository's tests/mutation/mutants.json)")
    ap.add_argument("--only", default="", help="comma-separated mutant ids to run (default: all)")
    ap.add_argument("--shaders-only", action="store_true", help="only the shader mutants (nothing is rebuilt)")
    ap.add_argument("--exe", default="",
                    help="a folder holding the puff_tests_* to run (default: BUILD/tests); a copy keeps a run "
                         "going while the build changes; shader mutants only")
    ap.add_argument("--out", default="", help="where mutants.csv and report.md go (default: BUILD/mutation)")
    ap.add_argument("--timeout", type=int, default=1200, help="seconds per run of one group (default: %(default)s)")
    ap.add_argument("--list", action="store_true", help="list the selected mutants and exit")
    args = ap.parse_args()

    spec = load(args.mutants)
    mutants = spec["mutants"]
    if args.only:
        want = [w for w in args.only.split(",") if w]
        unknown = [w for w in want if w not in {m["id"] for m in mutants}]
        if unknown:
            raise SetupError(f"unknown mutant ids: {', '.join(unknown)} (--list shows them)")
        mutants = [m for m in mutants if m["id"] in want]
    if args.shaders_only:
        mutants = [m for m in mutants if m["file"].startswith("shaders/")]
    if not mutants:
        raise SetupError("no mutant selected")
    if args.list:
        for m in mutants:
            print(f"{m['id']:28} {m['file']:34} {'+'.join(m['suites']):8} {m['what']}")
        return 0

    build_dir = Path(args.build).resolve()
    cxx = [m for m in mutants if not m["file"].startswith("shaders/")]
    exe_dir = Path(args.exe).resolve() if args.exe else build_dir / "tests"
    if args.exe and cxx:
        raise SetupError("--exe runs shader mutants only (C++ mutants rebuild BUILD's tests): add --shaders-only")
    out_dir = Path(args.out).resolve() if args.out else build_dir / "mutation"
    cwd = build_dir / "tests"  # where ctest runs the tests

    # Every mutant applies before anything runs (a stale mutant is an error in the list, not a kill).
    problems = []
    for m in mutants:
        try:
            mutate_text((ROOT / m["file"]).read_text(), m)
        except (OSError, ValueError) as e:
            problems.append(str(e))
    if problems:
        raise SetupError("\n".join(problems))
    if cxx:
        files = sorted({m["file"] for m in cxx})
        dirty = subprocess.run(["git", "-C", str(ROOT), "status", "--porcelain", "--"] + files,
                               stdout=subprocess.PIPE, text=True).stdout.strip()
        if dirty:
            raise SetupError(f"C++ mutants change files with uncommitted edits (commit or stash them):\n{dirty}")
        print("building the tests before the baseline", flush=True)
        ok, log = build(build_dir)
        if not ok:
            raise SetupError(f"the tests do not build:\n{log}")
    exes = test_executables(exe_dir)
    if not exes:
        raise SetupError(f"{exe_dir}: no puff_tests_* (build the tree first: cmake --build {args.build})")

    for s in (signal.SIGTERM, signal.SIGHUP):
        signal.signal(s, interrupt)
    work = Path(tempfile.mkdtemp(prefix="puff-mutation-"))
    saved = {}  # C++ sources in place: path -> original bytes
    rows, baselines, interrupted = [], {}, False
    try:
        pristine = work / "pristine-shaders"
        shutil.copytree(ROOT / "shaders", pristine)
        groups_needed = sorted({g for m in mutants for g in m["suites"]})
        for group in groups_needed:
            t0 = time.time()
            res, note, log = run_tests(exes, spec["suites"][group], pristine, args.timeout, work, cwd)
            if note or not res:
                raise SetupError(f"baseline {group}: {note or 'ran no test'}\n{log[-2000:]}")
            bad = sorted(t for t, r in res.items() if r != "pass")
            print(f"baseline {group}: {len(res)} tests, {len(bad)} not passing unmutated"
                  f"{' (' + ', '.join(bad) + ')' if bad else ''}, {time.time() - t0:.0f} s", flush=True)
            baselines[group] = res

        for i, m in enumerate(mutants, 1):
            t0 = time.time()
            path = ROOT / m["file"]
            row = dict(m, status="", note="", analytic=[], golden=[], seconds=0)
            mutated = mutate_text(path.read_text(), m)
            if m["file"].startswith("shaders/"):
                shader_dir = work / "shaders"
                if shader_dir.exists():
                    shutil.rmtree(shader_dir)
                shutil.copytree(pristine, shader_dir)
                (shader_dir / Path(m["file"]).relative_to("shaders")).write_text(mutated)
            else:
                shader_dir = pristine
                saved[path] = path.read_bytes()
                write_atomically(path, mutated)
                ok, log = build(build_dir)
                if not ok:
                    write_atomically(path, saved.pop(path).decode())
                    row.update(status="does not build", note=(log.strip().splitlines() or [""])[-1][:200],
                               seconds=round(time.time() - t0))
                    rows.append(row)
                    print(f"[{i}/{len(mutants)}] {m['id']}: does not build", flush=True)
                    continue
            killers, notes = [], []
            for group in m["suites"]:
                res, note, _ = run_tests(exes, spec["suites"][group], shader_dir, args.timeout, work, cwd)
                if note:
                    notes.append(f"{group}: {note}")
                killers += [t for t, r in baselines[group].items() if r == "pass" and res.get(t) == "fail"]
            if path in saved:
                write_atomically(path, saved.pop(path).decode())
                ok, log = build(build_dir)
                if not ok:
                    raise SetupError(f"the tests do not build after restoring {m['file']}:\n{log}")
            analytic = sorted({t for t in killers if not GOLDEN.search(t)})
            golden = sorted({t for t in killers if GOLDEN.search(t)})
            status = "killed" if analytic else ("golden only" if golden else ("error" if notes else "survived"))
            row.update(status=status, note="; ".join(notes), analytic=analytic, golden=golden,
                       seconds=round(time.time() - t0))
            rows.append(row)
            print(f"[{i}/{len(mutants)}] {m['id']}: {status} ({len(analytic)} analytic, {len(golden)} golden"
                  f"{'; ' + row['note'] if row['note'] else ''}) {row['seconds']} s", flush=True)
    except KeyboardInterrupt:
        interrupted = True
        print("stopped: putting the sources back", file=sys.stderr)
    finally:
        for path, data in saved.items():
            write_atomically(path, data.decode())
        if saved:
            ok, log = build(build_dir)
            if not ok:
                print(f"the tests do not build after restoring the sources:\n{log}", file=sys.stderr)
        shutil.rmtree(work, ignore_errors=True)

    if not rows:
        return 2 if interrupted else 0
    killed, golden_only, survived, scored, apart = write_reports(out_dir, rows, baselines, interrupted)
    print(f"\nscore: {len(killed)}/{len(scored)} killed by an analytic test; golden images alone: "
          f"{', '.join(golden_only) or 'none'}; not killed: {', '.join(survived) or 'none'}"
          f"{'; left out: ' + ', '.join(r['id'] for r in apart) if apart else ''}"
          f"{' (stopped early)' if interrupted else ''}")
    print(f"wrote {out_dir / 'mutants.csv'} and {out_dir / 'report.md'}")
    if interrupted:
        return 2
    return 0 if len(killed) == len(scored) and not apart else 1


if __name__ == "__main__":
    try:
        sys.exit(main())
    except SetupError as e:
        print(f"run.py: {e}", file=sys.stderr)
        sys.exit(2)
