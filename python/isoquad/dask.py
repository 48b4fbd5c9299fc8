"""isoquad on a Dask cluster, for more files than one machine remeshes in time.

    import isoquad.dask
    rows = isoquad.dask.remesh_many(paths, "out", quads=1500)       # a LocalCluster here

    from dask.distributed import Client
    rows = isoquad.dask.remesh_many(paths, "out", client=Client("tcp://scheduler:8786"))

Each file is one task, and each task runs `isoquad batch FILE` in a process of its own, so a crash
in one file cannot take a worker's other tasks with it; the outputs, the rows and the summary
table (OUT_DIR/summary.csv and .json) are those `isoquad batch` writes. The workers need the
isoquad command line (on PATH, or ISOQUAD_CLI) and out_dir on a file system they share.
"""

import csv
import json
import os
import shutil
import subprocess
import tempfile
from pathlib import Path

from . import InputError

__all__ = ["remesh_many", "batch_arguments", "command_line"]

_MESH_SUFFIXES = (".obj", ".off", ".ply", ".stl")

# Python option -> (command-line flag, kind): "value" passes the value, "flag" the flag when
# true, "negated" the flag when false.
_OPTIONS = {
    "quads": ("--quads", "value"),
    "edge_length": ("--edge-length", "value"),
    "patches": ("--patches", "value"),
    "seed": ("--seed", "value"),
    "weights": ("--weights", "value"),
    "relax": ("--relax", "value"),
    "segmentation": ("--segmentation", "value"),
    "corners": ("--corners", "value"),
    "improve_corners": ("--no-improve-corners", "negated"),
    "feature_angle": ("--feature-angle", "value"),
    "repair": ("--repair", "flag"),
    "weld_eps": ("--weld-eps", "value"),
    "smooth": ("--smooth", "value"),
    "untangle": ("--no-untangle", "negated"),
    "snap": ("--no-snap", "negated"),
    "fold_rounds": ("--fold-rounds", "value"),
    "split_patches": ("--split-patches", "flag"),
    "tip_split": ("--no-tip-split", "negated"),
    "refine": ("--no-refine", "negated"),
    "patch_rounds": ("--no-patch-rounds", "negated"),
    "misfit_split": ("--no-misfit-split", "negated"),
    "tolerance": ("--tolerance", "value"),
    "tolerance_rounds": ("--tolerance-rounds", "value"),
    "threads": ("--threads", "value"),
    "format": ("--format", "value"),
    "report": ("--report", "value"),
}


def batch_arguments(**options):
    """The `isoquad batch` arguments for remesh options named as isoquad.remesh names them
    (quads=1500, tip_split=False, weld_eps=0.01, ...), plus format ("obj", "off", "ply") and
    report (a folder). An unknown name is a TypeError."""
    args = []
    for name, value in options.items():
        if name not in _OPTIONS:
            raise TypeError(f"remesh_many got an unexpected option {name!r}")
        flag, kind = _OPTIONS[name]
        if value is None:
            continue
        if kind == "value":
            args += [flag, str(value)]
        elif bool(value) == (kind == "flag"):
            args.append(flag)
    return args


def command_line():
    """The isoquad command line the tasks run: ISOQUAD_CLI, else the one built or installed
    with this package, else `isoquad` on PATH."""
    found = os.environ.get("ISOQUAD_CLI")
    if not found:
        try:
            from ._paths import CLI
            found = CLI if os.access(CLI, os.X_OK) else None
        except ImportError:
            found = None
    found = found or shutil.which("isoquad")
    if not found:
        raise FileNotFoundError("no isoquad command line: install it or set ISOQUAD_CLI")
    return found


def _remesh_one(cli, path, out_dir, args):
    """One task: `isoquad batch PATH` in a process of its own; returns its summary row."""
    with tempfile.TemporaryDirectory(prefix="isoquad-task-") as tmp:
        stem = Path(tmp) / "row"
        done = subprocess.run([cli, "batch", str(path), "-o", str(out_dir), "--jobs", "1", "-q",
                               "--summary", str(stem), *args],
                              stdin=subprocess.DEVNULL, capture_output=True, text=True)
        try:
            with open(f"{stem}.json") as f:
                return json.load(f)["rows"][0]
        except (OSError, ValueError, KeyError, IndexError):
            return {"file": str(path), "output": None, "status": "crashed",
                    "exit_status": done.returncode, "error_code": "E700",
                    "error": (done.stderr or "ended without a summary").strip()[-2000:]}


def _expand(paths):
    files = []
    for p in map(Path, paths):
        if p.is_dir():
            files += sorted(f for f in p.iterdir()
                            if f.is_file() and f.suffix.lower() in _MESH_SUFFIXES)
        else:
            files.append(p)
    return files


def _write_summary(rows, stem, seconds):
    failed = sum(r["status"] in ("failed", "crashed") for r in rows)
    summary = {"files": len(rows), "ok": len(rows) - failed, "failed": failed,
               "seconds": seconds, "rows": rows}
    with open(f"{stem}.json", "w") as f:
        json.dump(summary, f, indent=2)
        f.write("\n")
    columns = list(rows[0].keys()) if rows else []
    with open(f"{stem}.csv", "w", newline="") as f:
        out = csv.writer(f, lineterminator="\n")
        out.writerow(columns)
        for r in rows:
            out.writerow(["" if r.get(c) is None else
                          (r[c] if isinstance(r[c], str) else json.dumps(r[c])) for c in columns])


def remesh_many(paths, out_dir, client=None, **options):
    """Remesh files (or the mesh files of folders) into out_dir, one Dask task per file; returns
    the summary table, one dictionary per file: file, output, status ("ok", "failed",
    "crashed"), exit_status, error_code, error, quads, irregular, scaled_jacobian_min,
    scaled_jacobian_mean, folded, hausdorff, mean_distance, seconds; and writes it as
    out_dir/summary.csv and summary.json, as `isoquad batch` does.

    client: a dask.distributed Client; None starts a LocalCluster with one single-threaded
    worker process per core for the call. options: those of isoquad.remesh (quads=1500,
    tip_split=False, ...) and format and report (see batch_arguments).
    """
    import time

    from dask.distributed import Client, LocalCluster

    start = time.monotonic()
    files = _expand(paths)
    outputs = {}
    for f in files:
        if f.stem in outputs:
            raise InputError(f"{outputs[f.stem]} and {f} would both be written as {f.stem} "
                             "[E003]", "E003", 2)
        outputs[f.stem] = f
    out_dir = Path(out_dir).resolve()
    out_dir.mkdir(parents=True, exist_ok=True)
    cli = command_line()
    own = client is None
    if own:
        cluster = LocalCluster(n_workers=os.cpu_count() or 1, threads_per_worker=1,
                               processes=True, dashboard_address=None)
        client = Client(cluster)
        # One file per core already: each file on one thread (the same quads for any count).
        options.setdefault("threads", 1)
    try:
        args = batch_arguments(**options)
        futures = client.map(_remesh_one, [cli] * len(files), [str(f.resolve()) for f in files],
                             [str(out_dir)] * len(files), [args] * len(files), pure=False)
        rows = client.gather(futures)
    finally:
        if own:
            client.close()
            cluster.close()
    _write_summary(rows, out_dir / "summary", time.monotonic() - start)
    return rows
