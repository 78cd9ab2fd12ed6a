#!/usr/bin/env python3
"""Byte-mutated copies of valid files, run through the tools as a user would.

For each format, N copies of the seed files in tests/fuzz/corpus (and
tests/fuzz/seeds: the interchange formats, which no harness reads) with 1 to
16 random bytes changed, each run through `sdftrace render --grid` (grids),
`mesh2sdf` (meshes) or `mesh2sdf spot.obj --query FILE` (npy) with a time
limit and an address-space limit; tallies per format: clean error (non-zero
exit, one line on stderr, no output file), success, crash, hang, out of
memory (std::bad_alloc, even in a one-line error, or killed), and the untidy
(an error with several lines or a half-written output, or any run that
leaves another file behind). Prints a Markdown table; the inputs that
crashed, hung, ran out of memory or failed untidily are kept under
OUT/<format>/.

  tests/fuzz/mutate.py --build build --count 1000 --out /tmp/mutate
"""
import argparse
import os
import random
import resource
import shutil
import signal
import subprocess
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
CORPUS = os.path.join(HERE, "corpus")
SEEDS = os.path.join(HERE, "seeds")
SPOT = os.path.join(HERE, "..", "data", "meshes", "spot.obj")

# format: (seed folder, file-name filter, extension, whether the seed
# files carry the mesh harness's leading format byte)
FORMATS = {
    "vdb": ("vdb", lambda n: n.endswith(".vdb"), ".vdb", False),
    "nvdb": ("nvdb", lambda n: n.endswith(".nvdb"), ".nvdb", False),
    "obj": ("mesh", lambda n: n.endswith(".obj"), ".obj", True),
    "ply-ascii": ("mesh", lambda n: n.endswith("_ascii.ply"), ".ply", True),
    "ply-binary": ("mesh", lambda n: n.endswith(".ply") and not n.endswith("_ascii.ply"), ".ply", True),
    "off": ("mesh", lambda n: n.endswith(".off"), ".off", True),
    "stl-ascii": ("mesh", lambda n: n.endswith("_ascii.stl"), ".stl", True),
    "stl-binary": ("mesh", lambda n: n.endswith("_binary.stl"), ".stl", True),
    "om": ("mesh", lambda n: n.endswith(".om"), ".om", True),
    "npy": ("npy", lambda n: n.endswith(".npy"), ".npy", False),
    "glb": (SEEDS, lambda n: n.endswith(".glb"), ".glb", False),
    "gltf": (SEEDS, lambda n: n.endswith(".gltf"), ".gltf", False),
    "dae": (SEEDS, lambda n: n.endswith(".dae"), ".dae", False),
    "3mf": (SEEDS, lambda n: n.endswith(".3mf"), ".3mf", False),
    "fbx": (SEEDS, lambda n: n.endswith(".fbx"), ".fbx", False),
}
OUTCOMES = ["clean error", "success", "untidy error", "crash", "hang", "out of memory"]


def seeds(fmt):
    folder, keep, _, prefixed = FORMATS[fmt]
    folder = os.path.join(CORPUS, folder)  # an absolute folder stays itself
    out = []
    for name in sorted(os.listdir(folder)):
        if keep(name):
            with open(os.path.join(folder, name), "rb") as f:
                data = f.read()
            out.append(data[1:] if prefixed else data)
    return out


def mutate(data, rng):
    b = bytearray(data)
    for _ in range(rng.randint(1, 16)):
        b[rng.randrange(len(b))] = rng.randrange(256)
    return bytes(b)


def command(args, fmt, path, output):
    if fmt in ("vdb", "nvdb"):
        return [os.path.join(args.build, "sdftrace"), "render", "--grid", path, "-o", output, "--width", "32",
                "--height", "24", "--quiet", "--threads", "1"]
    if fmt == "npy":
        return [os.path.join(args.build, "mesh2sdf"), SPOT, "--query", path, output, "--quiet", "--threads", "1"]
    return [os.path.join(args.build, "mesh2sdf"), path, "-o", output, "--res", "16", "--quiet", "--threads", "1"]


def run(cmd, timeout, memory):
    def limit():
        resource.setrlimit(resource.RLIMIT_AS, (memory, memory))
        os.setsid()

    p = subprocess.Popen(cmd, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, preexec_fn=limit)
    try:
        _, err = p.communicate(timeout=timeout)
    except subprocess.TimeoutExpired:
        os.killpg(p.pid, signal.SIGKILL)
        p.communicate()
        return "hang", b""
    return p.returncode, err


def classify(rc, err, output):
    if rc == "hang":
        return "hang"
    text = err.decode("utf-8", "replace")
    if "bad_alloc" in text or ("out of memory" in text.lower() and rc < 0) or rc == -signal.SIGKILL:
        return "out of memory"
    if rc < 0 or "Sanitizer" in text or "terminate called" in text:
        return "crash"
    if rc == 0:
        return "success"
    lines = [l for l in text.splitlines() if l.strip()]
    if len(lines) != 1 or os.path.exists(output):
        return "untidy error"
    return "clean error"


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--build", default="build", help="folder with sdftrace and mesh2sdf (default build)")
    ap.add_argument("--count", type=int, default=1000, help="mutated files per format (default 1000)")
    ap.add_argument("--out", default="/tmp/sdft-mutate", help="work folder; kept: the failing inputs")
    ap.add_argument("--formats", default=",".join(FORMATS), help="comma-separated, of: " + ", ".join(FORMATS))
    ap.add_argument("--timeout", type=float, default=20.0, help="seconds per run before it counts as a hang")
    ap.add_argument("--memory-gib", type=float, default=4.0, help="address-space limit per run (ulimit -v)")
    ap.add_argument("--seed", type=int, default=1, help="random seed")
    args = ap.parse_args()
    rng = random.Random(args.seed)
    memory = int(args.memory_gib * (1 << 30))
    rows = []
    for fmt in args.formats.split(","):
        if fmt not in FORMATS:
            sys.exit(f"mutate.py: unknown format '{fmt}' (of: {', '.join(FORMATS)})")
        pool = seeds(fmt)
        ext = FORMATS[fmt][2]
        work = os.path.join(args.out, fmt)
        os.makedirs(work, exist_ok=True)
        tally = dict.fromkeys(OUTCOMES, 0)
        for i in range(args.count):
            path = os.path.join(work, f"input{ext}")
            output = os.path.join(work, {"vdb": "out.exr", "nvdb": "out.exr", "npy": "out.npy"}.get(fmt, "out.vdb"))
            with open(path, "wb") as f:
                f.write(mutate(rng.choice(pool), rng))
            if os.path.exists(output):
                os.unlink(output)
            before = set(os.listdir(work))
            rc, err = run(command(args, fmt, path, output), args.timeout, memory)
            outcome = classify(rc, err, output)
            # a file left beside the output is untidy too (a success's
            # sidecar, out.json, is not; its output is deleted next run)
            stem = os.path.splitext(os.path.basename(output))[0]
            stray = set(os.listdir(work)) - before - {os.path.basename(output)}
            stray -= {stem + ".json"} if outcome == "success" else set()
            if stray and outcome in ("clean error", "success"):
                outcome = "untidy error"
            for name in stray:
                os.unlink(os.path.join(work, name))
            tally[outcome] += 1
            if outcome not in ("clean error", "success"):
                kept = os.path.join(work, f"{outcome.replace(' ', '-')}-{i:04d}{ext}")
                shutil.copy(path, kept)
                with open(kept + ".stderr", "wb") as f:
                    f.write(err)
        rows.append((fmt, tally))
        print(f"{fmt}: {tally}", file=sys.stderr, flush=True)
    print("| input | " + " | ".join(OUTCOMES) + " |")
    print("|---|" + "---|" * len(OUTCOMES))
    for fmt, tally in rows:
        print(f"| {fmt} | " + " | ".join(str(tally[o]) for o in OUTCOMES) + " |")


if __name__ == "__main__":
    main()
