"""isoquad.dask.remesh_many on a two-worker LocalCluster: the same outputs and rows as
`isoquad batch` (python3-dask, python3-distributed)."""

import filecmp
import json
import os
import subprocess
import tempfile
import unittest
from pathlib import Path

import isoquad
import isoquad.dask

SOURCE = Path(os.environ.get("ISOQUAD_SOURCE_DIR", Path(__file__).resolve().parents[2]))
DATA = SOURCE / "data"
# The columns both write; seconds differ from run to run.
SAME = ("status", "exit_status", "error_code", "quads", "irregular", "scaled_jacobian_min",
        "scaled_jacobian_mean", "folded", "hausdorff", "mean_distance")


class RemeshMany(unittest.TestCase):
    def test_gives_the_outputs_and_rows_of_batch(self):
        with tempfile.TemporaryDirectory() as tmp:
            tmp = Path(tmp)
            broken = tmp / "broken.off"
            broken.write_text("OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 7\n")
            paths = [DATA / "sphere.off", DATA / "fandisk.off", DATA / "nefertiti.off", broken]
            done = subprocess.run([isoquad.dask.command_line(), "batch", *map(str, paths), "-o",
                                   str(tmp / "batch"), "--quads", "300", "-q"])
            self.assertEqual(done.returncode, 1)
            from dask.distributed import Client, LocalCluster
            with LocalCluster(n_workers=2, threads_per_worker=1, processes=True,
                              dashboard_address=None) as cluster, Client(cluster) as client:
                rows = isoquad.dask.remesh_many(paths, tmp / "dask", client=client, quads=300)
            batch = {Path(r["file"]).name: r
                     for r in json.loads((tmp / "batch" / "summary.json").read_text())["rows"]}
            self.assertEqual([Path(r["file"]).name for r in rows], [p.name for p in paths])
            for row in rows:
                name = Path(row["file"]).name
                for column in SAME:
                    self.assertEqual(row[column], batch[name][column], f"{name} {column}")
            self.assertEqual(batch["broken.off"]["status"], "failed")
            for p in paths[:3]:
                out = p.stem + ".obj"
                self.assertTrue(filecmp.cmp(tmp / "batch" / out, tmp / "dask" / out,
                                            shallow=False), out)
            summary = json.loads((tmp / "dask" / "summary.json").read_text())
            self.assertEqual((summary["files"], summary["ok"], summary["failed"]), (4, 3, 1))
            header = (tmp / "dask" / "summary.csv").read_text().splitlines()[0]
            self.assertEqual(header, (tmp / "batch" / "summary.csv").read_text().splitlines()[0])

    def test_without_a_client_it_starts_a_local_cluster(self):
        with tempfile.TemporaryDirectory() as tmp:
            rows = isoquad.dask.remesh_many([DATA / "sphere.off"], Path(tmp) / "out", quads=300)
            self.assertEqual([r["status"] for r in rows], ["ok"])
            self.assertTrue((Path(tmp) / "out" / "sphere.obj").exists())

    def test_options_become_batch_flags_the_command_line_knows(self):
        options = {name: 1 for name in isoquad.dask._OPTIONS}
        options.update(weights="mvc", relax="locked", segmentation="field", corners="local",
                       format="off", report="r", patches="auto")
        for name in ("improve_corners", "untangle", "snap", "tip_split", "refine",
                     "patch_rounds", "misfit_split"):
            options[name] = False
        options.update(repair=True, split_patches=True)
        args = isoquad.dask.batch_arguments(**options)
        usage = subprocess.run([isoquad.dask.command_line(), "batch", "--help"],
                               capture_output=True, text=True, check=True).stdout
        flags = [a for a in args if a.startswith("--")]
        self.assertEqual(len(flags), len(options))
        for flag in flags:
            self.assertIn(flag, usage)
        self.assertEqual(isoquad.dask.batch_arguments(tip_split=True, repair=False), [])
        with self.assertRaises(TypeError):
            isoquad.dask.batch_arguments(quad=300)

    def test_inputs_of_the_same_name_are_refused(self):
        with tempfile.TemporaryDirectory() as tmp:
            (Path(tmp) / "sphere.off").write_text((DATA / "sphere.off").read_text())
            with self.assertRaises(isoquad.InputError) as caught:
                isoquad.dask.remesh_many([DATA / "sphere.off", Path(tmp) / "sphere.off"],
                                         Path(tmp) / "out", client=object())
            self.assertEqual(caught.exception.code, "E003")


if __name__ == "__main__":
    unittest.main()
