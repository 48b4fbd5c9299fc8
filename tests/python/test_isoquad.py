"""The Python module (python/isoquad): run by ctest with PYTHONPATH at the build's python/
folder, ISOQUAD_CLI the command line, ISOQUAD_SOURCE_DIR the source tree."""

import ast
import filecmp
import inspect
import os
import pickle
import subprocess
import threading
import time
import unittest
from pathlib import Path

import numpy as np

import isoquad

SOURCE = Path(os.environ.get("ISOQUAD_SOURCE_DIR", Path(__file__).resolve().parents[2]))
CLI = os.environ.get("ISOQUAD_CLI", "")
DATA = SOURCE / "data"


def corpus_mesh(name):
    folder = os.environ.get("ISOQUAD_CORPUS_DIR", "")
    path = Path(folder) / name
    if folder and path.exists():
        return path
    if os.environ.get("ISOQUAD_REQUIRE_CORPUS") == "1":
        raise AssertionError(f"corpus mesh {path} missing (ISOQUAD_REQUIRE_CORPUS=1)")
    raise unittest.SkipTest(f"no corpus mesh {name} (set ISOQUAD_CORPUS_DIR)")


def moebius_strip(n=24):
    """A non-orientable strip: n quads around, two triangles each, the ends glued twisted."""
    t = np.linspace(0, 2 * np.pi, n, endpoint=False)
    V = []
    for s in (-0.3, 0.3):
        V.append(np.stack([(1 + s * np.cos(t / 2)) * np.cos(t),
                           (1 + s * np.cos(t / 2)) * np.sin(t), s * np.sin(t / 2)], axis=1))
    V = np.concatenate(V)
    F = []
    for i in range(n):
        a, b = i, n + i
        if i + 1 < n:
            c, d = i + 1, n + i + 1
        else:  # half a turn: the inner edge meets the outer one
            c, d = n, 0
        F += [[a, c, b], [b, c, d]]
    return V, np.array(F)


class Remesh(unittest.TestCase):
    def test_matches_the_command_line_bit_for_bit(self):
        path = corpus_mesh("fandisk.off")
        tmp = Path(self.tmp.name)
        cli_out, py_out = tmp / "cli.obj", tmp / "py.obj"
        subprocess.run([CLI, "remesh", str(path), "-o", str(cli_out), "--quads", "1500", "-q"],
                       check=True)
        V, F = isoquad.read(path)
        result = isoquad.remesh(V, F, quads=1500)
        Vq, Q, report = result
        isoquad.write(py_out, Vq, Q, result.patch)
        self.assertTrue(filecmp.cmp(cli_out, py_out, shallow=False))
        Vc, Qc = isoquad.read(cli_out)
        self.assertTrue(np.array_equal(Vc, Vq))
        self.assertTrue(np.array_equal(Qc, Q))
        self.assertEqual(Vq.dtype, np.float64)
        self.assertEqual(Q.shape, (report["quads"], 4))
        self.assertTrue(report["quality"]["pure_quad"])
        self.assertEqual(report["options"]["quads"], 1500)

    def test_progress_covers_every_stage_and_never_goes_down(self):
        V, F = isoquad.read(DATA / "sphere.off")
        for segmentation in ("vsa", "field"):
            with self.subTest(segmentation=segmentation):
                calls = []
                caller = threading.get_ident()
                isoquad.remesh(V, F, quads=300, segmentation=segmentation,
                               progress=lambda f, s, m: calls.append((f, s, m,
                                                                      threading.get_ident())))
                fractions = [f for f, _, _, _ in calls]
                self.assertEqual(fractions, sorted(fractions))
                self.assertEqual(fractions[0], 0)
                self.assertEqual(fractions[-1], 1)
                self.assertEqual(calls[-1][1], "done")
                self.assertEqual({t for _, _, _, t in calls}, {caller})
                # The stages inside a component, each as it begins (repairs run some again).
                stages = list(dict.fromkeys(s for _, s, _, _ in calls))
                self.assertEqual(stages, ["prepare", "segment", "layout", "map", "extract",
                                          "repair", "quality", "done"])
                self.assertTrue(any(m.startswith("component 0: segment") for _, _, m, _ in calls))

    def test_allow_topology_change_is_passed_and_echoed(self):
        V, F = isoquad.read(DATA / "sphere.off")
        for allow in (False, True):
            _, _, report = isoquad.remesh(V, F, quads=300, quality=False,
                                          allow_topology_change=allow)
            self.assertIs(report["options"]["allow_topology_change"], allow)
            self.assertFalse(any(w["code"] == "W113" for w in report["warnings"]))

    def test_allow_invalid_is_passed_and_echoed(self):
        V, F = isoquad.read(DATA / "sphere.off")
        for allow in (False, True):
            _, _, report = isoquad.remesh(V, F, quads=300, quality=False, allow_invalid=allow)
            self.assertIs(report["options"]["allow_invalid"], allow)
            self.assertFalse(any(w["code"] == "W117" for w in report["warnings"]))

    def test_the_report_has_the_peak_memory(self):
        # getrusage's peak for the whole process, this one's numpy included: more than a MB.
        V, F = isoquad.read(DATA / "sphere.off")
        _, _, report = isoquad.remesh(V, F, quads=300, quality=False)
        self.assertIsInstance(report["peak_rss_bytes"], int)
        self.assertGreater(report["peak_rss_bytes"], 1 << 20)

    def test_an_exception_in_the_progress_callback_ends_the_run(self):
        V, F = isoquad.read(DATA / "sphere.off")

        def stop(fraction, stage, message):
            if stage == "map":
                raise KeyboardInterrupt("stopped")

        with self.assertRaises(KeyboardInterrupt):
            isoquad.remesh(V, F, quads=300, progress=stop)

    def test_the_gil_is_released_while_it_runs(self):
        # Fandisk at its default size, seconds of work: were the GIL held, this thread would
        # stand still through all of it. A loaded machine may pause it now and then, briefly.
        V, F = isoquad.read(DATA / "fandisk.off")
        ticks = []
        done = threading.Event()
        worker = threading.Thread(target=lambda: (isoquad.remesh(V, F), done.set()))
        start = time.perf_counter()
        worker.start()
        while not done.is_set():
            ticks.append(time.perf_counter())
            time.sleep(0.005)
        worker.join()
        run = time.perf_counter() - start
        self.assertGreater(run, 0.5)
        self.assertGreater(len(ticks), 20)
        self.assertLess(max(np.diff(ticks)), run / 3)

    def test_quality_with_and_without_a_reference(self):
        V, F = isoquad.read(DATA / "sphere.off")
        Vq, Q, _ = isoquad.remesh(V, F, quads=300, quality=False)
        alone = isoquad.quality(Vq, Q)
        self.assertTrue(alone["pure_quad"])
        self.assertNotIn("hausdorff", alone)
        measured = isoquad.quality(Vq, Q, reference=(V, F))
        self.assertTrue(measured["same_topology"])
        self.assertLess(measured["hausdorff"], 0.02)

    def setUp(self):
        import tempfile
        self.tmp = tempfile.TemporaryDirectory()

    def tearDown(self):
        self.tmp.cleanup()


class Files(unittest.TestCase):
    def test_write_then_read_is_bit_exact(self):
        import tempfile
        V, F = isoquad.read(DATA / "fandisk.off")
        self.assertEqual(F.shape[1], 3)
        with tempfile.TemporaryDirectory() as tmp:
            for ext in ("obj", "off", "ply"):
                path = Path(tmp) / f"m.{ext}"
                isoquad.write(path, V, F)
                V2, F2 = isoquad.read(path)
                self.assertTrue(np.array_equal(V, V2), ext)
                self.assertTrue(np.array_equal(F, F2), ext)

    def test_mixed_polygons_are_padded_with_minus_one(self):
        import tempfile
        with tempfile.TemporaryDirectory() as tmp:
            path = Path(tmp) / "mixed.obj"
            path.write_text("v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 2 0 0\n"
                            "f 1 2 3 4\nf 2 5 3\n")
            V, F = isoquad.read(path)
            self.assertEqual(F.tolist(), [[0, 1, 2, 3], [1, 4, 2, -1]])
            isoquad.write(Path(tmp) / "again.obj", V, F)
            self.assertEqual(isoquad.read(Path(tmp) / "again.obj")[1].tolist(), F.tolist())


class Errors(unittest.TestCase):
    def assert_raises(self, kind, code, call, *args, **kwargs):
        with self.assertRaises(kind) as caught:
            call(*args, **kwargs)
        e = caught.exception
        self.assertIsInstance(e, isoquad.Error)
        self.assertEqual(e.code, code, e.message)
        self.assertTrue(str(e).endswith(f"[{code}]"), str(e))
        return e

    def test_a_malformed_file_is_an_input_error_with_its_line(self):
        import tempfile
        with tempfile.TemporaryDirectory() as tmp:
            path = Path(tmp) / "bad.off"
            path.write_text("OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 7\n")
            e = self.assert_raises(isoquad.InputError, "E012", isoquad.read, path)
            self.assertEqual(e.exit_status, 2)
            self.assertEqual(e.file, str(path))
            self.assertEqual(e.line, 6)
        self.assert_raises(isoquad.InputError, "E001", isoquad.read, "/nonexistent/mesh.off")

    def test_options_out_of_range_are_input_errors(self):
        V, F = isoquad.read(DATA / "sphere.off")
        for options in ({"quads": -5}, {"edge_length": float("nan")}, {"relax": "loose"},
                        {"segmentation": "voronoi"}, {"weights": "cot"}, {"corners": "both"},
                        {"tolerance": 2.0}, {"feature_angle": 200}, {"weld_eps": 0.5}, {"smooth": -1},
                        {"quads": 100, "edge_length": 0.1}, {"patches": 0}):
            with self.subTest(options=options):
                self.assert_raises(isoquad.InputError, "E003", isoquad.remesh, V, F, **options)

    def test_an_unknown_option_is_a_type_error(self):
        V, F = isoquad.read(DATA / "sphere.off")
        with self.assertRaises(TypeError):
            isoquad.remesh(V, F, quad=300)

    def test_an_index_out_of_range_is_an_input_error(self):
        V, F = isoquad.read(DATA / "sphere.off")
        F = F.copy()
        F[3, 1] = len(V)
        e = self.assert_raises(isoquad.InputError, "E020", isoquad.remesh, V, F)
        self.assertEqual(e.faces, [3])

    def test_a_non_orientable_surface_is_a_topology_error(self):
        V, F = moebius_strip()
        self.assert_raises(isoquad.TopologyError, "E102", isoquad.remesh, V, F)

    def test_a_non_manifold_edge_is_an_input_error_unless_repaired(self):
        V, F = isoquad.read(DATA / "sphere.off")
        apex = len(V)
        V = np.vstack([V, [[0, 0, 3]]])
        F = np.vstack([F, [[F[0, 0], F[0, 1], apex]]])
        self.assert_raises(isoquad.InputError, "E101", isoquad.remesh, V, F, quads=300)

    def test_a_far_too_large_edge_length_is_a_layout_error(self):
        V, F = isoquad.read(DATA / "sphere.off")
        e = self.assert_raises(isoquad.LayoutError, "E501", isoquad.remesh, V, F, edge_length=1e3)
        self.assertEqual(e.exit_status, 4)

    def test_a_vertex_on_its_neighbour_is_repaired_and_remeshed(self):
        # Coincident vertices and zero-area triangles: the edge between them is collapsed before
        # anything else (W116), as in the command line's test
        # Cli.RemeshJsonStdoutIsOneDocumentWhateverHappens; the map's matrix was singular (E551).
        V, F = isoquad.read(DATA / "sphere.off")
        face = next(f for f in F if 5 in f)
        V = V.copy()
        V[5] = V[face[(list(face).index(5) + 1) % 3]]
        _, _, report = isoquad.remesh(V, F, quads=300)
        self.assertIn("W116", [w["code"] for w in report["warnings"]])
        self.assertTrue(report["quality"]["same_topology"])
        self.assertEqual(report["quality"]["scaled_jacobian"]["at_most_0.001"], 0)

    def test_bad_shapes_and_dtypes_are_value_errors(self):
        V, F = isoquad.read(DATA / "sphere.off")
        for bad_v, bad_f in ((V[:, :2], F), (V.astype(str), F), (V, F.astype(np.float64)),
                             (V, F[:, :2]), (V[0], F), (V, F.astype(complex))):
            with self.subTest(v=(bad_v.shape, bad_v.dtype), f=(bad_f.shape, bad_f.dtype)):
                with self.assertRaises(ValueError):
                    isoquad.remesh(bad_v, bad_f)
        with self.assertRaises(ValueError):
            isoquad.quality(V, F, reference=V)

    def test_errors_pickle_with_their_attributes(self):
        e = isoquad.LayoutError("no layout [E402]", "E402", 4, "", None, [1], [2, 3])
        again = pickle.loads(pickle.dumps(e))
        self.assertIs(type(again), isoquad.LayoutError)
        self.assertEqual((again.code, again.exit_status, again.faces), ("E402", 4, [2, 3]))


class Interface(unittest.TestCase):
    def test_the_stubs_declare_every_public_name_with_its_parameters(self):
        stubs = Path(isoquad.__file__).with_name("__init__.pyi")
        tree = ast.parse(stubs.read_text())
        declared = {}
        for node in tree.body:
            if isinstance(node, (ast.FunctionDef, ast.ClassDef)):
                declared[node.name] = node
        for name in isoquad.__all__:
            self.assertIn(name, declared, f"{name} is not in {stubs.name}")
            node, runtime = declared[name], getattr(isoquad, name)
            if isinstance(node, ast.FunctionDef):
                stub_args = [a.arg for a in node.args.args + node.args.kwonlyargs]
                self.assertEqual(stub_args, list(inspect.signature(runtime).parameters), name)

    def test_help_names_every_option(self):
        doc = isoquad.remesh.__doc__
        for name in inspect.signature(isoquad.remesh).parameters:
            if name not in ("V", "F"):
                self.assertIn(f"  {name} ", doc, name)
        for name in isoquad.__all__:
            self.assertTrue(getattr(isoquad, name).__doc__, name)


if __name__ == "__main__":
    unittest.main()
