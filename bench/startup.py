#!/usr/bin/env python3
"""How long squama takes to start: a command without images (--version, params), one that
writes images (render at 64 px, which opens the image module and OpenImageIO's libraries),
and how many shared libraries each loads. Medians of --runs runs (default 11), in ms.
Ends with: RESULT startup version_ms=... params_ms=... render_ms=... libs_version=... libs_render=..."""
import argparse, glob, os, statistics, subprocess, sys, tempfile, time


def median_ms(cmd, runs):
    times = []
    for _ in range(runs):
        start = time.perf_counter()
        subprocess.run(cmd, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL, check=True)
        times.append(time.perf_counter() - start)
    return 1000 * statistics.median(times)


def libraries(cmd, tmp):
    """Shared objects the loader mapped (LD_DEBUG=files: one link map each)."""
    log = os.path.join(tmp, "ld")
    for f in glob.glob(log + ".*"):
        os.remove(f)
    env = dict(os.environ, LD_DEBUG="files", LD_DEBUG_OUTPUT=log)
    subprocess.run(cmd, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL, env=env, check=True)
    return sum("generating link map" in line
               for f in glob.glob(log + ".*") for line in open(f, errors="replace"))


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--squama", required=True)
    ap.add_argument("--preset", default="presets/thesis/table_4_4_spots.json")
    ap.add_argument("--runs", type=int, default=11)
    a = ap.parse_args()
    with tempfile.TemporaryDirectory() as tmp:
        cmds = {
            "version": [a.squama, "--version"],
            "params": [a.squama, "params"],
            "render": [a.squama, "render", a.preset, "-o", os.path.join(tmp, "r"), "--size", "64"],
        }
        ms = {k: median_ms(c, a.runs) for k, c in cmds.items()}
        libs = {k: libraries(cmds[k], tmp) for k in ("version", "render")}
    for k in cmds:
        print(f"{k:8s} {ms[k]:7.1f} ms" + (f"  {libs[k]} libraries" if k in libs else ""))
    print(f"RESULT startup version_ms={ms['version']:.1f} params_ms={ms['params']:.1f} "
          f"render_ms={ms['render']:.1f} libs_version={libs['version']} libs_render={libs['render']} "
          f"runs={a.runs}")


if __name__ == "__main__":
    sys.exit(main())
