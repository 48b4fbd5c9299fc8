"""isoquad: a triangle mesh in, a pure quad mesh out (the temperature-contour method).

    import isoquad
    V, F = isoquad.read("fandisk.off")
    Vq, Q, report = isoquad.remesh(V, F, quads=1500)
    isoquad.write("fandisk_quads.obj", Vq, Q)
    print(report["quality"]["hausdorff"])

Arrays are numpy: V float64 (n, 3), F integer (m, 3), quads Q (q, 4). Every failure of the
library is an isoquad.Error subclass (InputError, TopologyError, LayoutError, SolverError,
ExtractionError, InternalError) with the code and message the command line prints; a bad array
shape or dtype is a ValueError. The GIL is released while the library works.
"""

import json as _json

import numpy as _np

from . import _core

__version__ = _core.version()

__all__ = [
    "Error",
    "InputError",
    "TopologyError",
    "LayoutError",
    "SolverError",
    "ExtractionError",
    "InternalError",
    "RemeshResult",
    "Mesh",
    "remesh",
    "read",
    "write",
    "quality",
    "tune_allocator",
]


class Error(Exception):
    """A failure of isoquad, as the command line reports it.

    Attributes: message (the whole text, ending in [CODE]), code (E001 ...; the README's
    table), exit_status (the command line's: 2 input, 3 topology, 4 layout, 5 solver,
    6 extraction, 70 internal), file and line (where in a file, or "" and None), vertices and
    faces (the input elements at fault, 0-based).
    """

    def __init__(self, message, code, exit_status, file="", line=None, vertices=(), faces=()):
        super().__init__(message)
        self.message = message
        self.code = code
        self.exit_status = exit_status
        self.file = file
        self.line = line
        self.vertices = list(vertices)
        self.faces = list(faces)

    def __reduce__(self):
        return (type(self), (self.message, self.code, self.exit_status, self.file, self.line,
                             self.vertices, self.faces))


class InputError(Error):
    """Invalid input (exit status 2): an unreadable or malformed file, a non-manifold mesh, an
    option out of its range (E003), an index out of range (E020), ..."""


class TopologyError(Error):
    """A valid mesh the method cannot handle (exit status 3), e.g. a non-orientable one."""


class LayoutError(Error):
    """No feasible quad layout (exit status 4)."""


class SolverError(Error):
    """A linear or integer solver failed (exit status 5)."""


class ExtractionError(Error):
    """Quad extraction failed (exit status 6)."""


class InternalError(Error):
    """An invariant was violated (exit status 70): a bug in isoquad, please report it."""


class RemeshResult(tuple):
    """(V, Q, report) as remesh returns it; .patch holds each quad's patch id."""

    def __new__(cls, V, Q, report, patch):
        self = super().__new__(cls, (V, Q, report))
        self.patch = patch
        return self


class Mesh(tuple):
    """(V, F) as read returns it; .unshared_vertices is True for STL files, whose faces each
    have their own vertices: pass weld_all=True to remesh them (the command line does)."""

    def __new__(cls, V, F, unshared_vertices):
        self = super().__new__(cls, (V, F))
        self.unshared_vertices = unshared_vertices
        return self


def _refuse(what):
    return InputError(f"{what} [E003]", "E003", 2)


def _vertices(V, name):
    a = _np.asarray(V)
    if a.dtype.kind not in "fiu":
        raise ValueError(f"{name} must hold real coordinates (float64), not dtype {a.dtype}")
    if a.ndim != 2 or a.shape[1] != 3:
        raise ValueError(f"{name} must have shape (n, 3), not {a.shape}")
    return _np.ascontiguousarray(a, dtype=_np.float64)


def _faces(F, name, columns=None):
    a = _np.asarray(F)
    if a.dtype.kind not in "iu":
        raise ValueError(f"{name} must hold integer vertex indices, not dtype {a.dtype}")
    if a.ndim != 2 or a.shape[1] < 3 or (columns is not None and a.shape[1] != columns):
        want = f"(m, {columns})" if columns else "(m, 3), or (m, k) for polygons padded with -1"
        raise ValueError(f"{name} must have shape {want}, not {a.shape}")
    if a.size and (a.min() < -1 or a.max() > _np.iinfo(_np.int32).max):
        raise ValueError(f"{name} must hold indices from 0 to 2**31 - 1 (-1 pads polygons)")
    return _np.ascontiguousarray(a, dtype=_np.int32)


def _count(name, value, low=0):
    if isinstance(value, bool) or not isinstance(value, (int, _np.integer)) or value < low:
        raise _refuse(f"{name} {value!r} is not an integer of at least {low}")
    return int(value)


def _choice(name, value, choices):
    if value not in choices:
        raise _refuse(f"unknown {name} {value!r} ({' or '.join(choices)})")
    return value


def remesh(V, F, quads=None, edge_length=None, *, patches="auto", seed=1, weights="smvc",
           relax="adaptive", segmentation="vsa", corners="global", improve_corners=True,
           feature_angle=60.0, repair=False, weld_eps=0.0, weld_all=False, smooth=None,
           untangle=True, snap=True, fold_rounds=2, split_patches=False, tip_split=True,
           refine=True, patch_rounds=True, misfit_split=True, tolerance=0.0, tolerance_rounds=2,
           allow_topology_change=False, allow_invalid=False, threads=0, quality=True,
           progress=None):
    """Remesh a triangle mesh into a pure quad mesh: returns (V, Q, report).

    V: float64 (n, 3) positions; F: integer (m, 3) triangles (or (m, k) polygons padded with
    -1, as read returns them). Returns Vq float64 (k, 3), Q int32 (q, 4) counter-clockwise seen
    from outside, and report, the dictionary `isoquad remesh --json` prints (per-component
    stages, counts, timings, warnings and, with quality=True, report["quality"]). The result
    also has .patch, each quad's patch id. Same options, same quads as the command line.

    Size (at most one of the two; neither: one quad per 8 input triangles, 1,000 to 20,000):
      quads            target number of quads (the size is tuned to land near it)
      edge_length      target quad edge length, in input units
    Patches and layout:
      patches          number of VSA patches, or "auto" (from the VSA error drop)
      seed             random seed (default 1)
      segmentation     "vsa" (the paper's planar regions) or "field" (cut along the
                       streamlines of a cross field; VSA where it fails)
      corners          "global" or "local" (the paper's per-patch choice)
      improve_corners  refine the corners against the relaxed length program (default True)
      split_patches    split every patch into four-sided ones first (the paper's section 5)
    Map:
      weights          "smvc" (symmetrized, SPD) or "mvc" (the paper's mean value weights)
      relax            seam weights: "adaptive", "bisection" (the paper's) or "locked"
    Repairs of the quads (each on by default):
      untangle         move corners of quads folded against the surface
      snap             move corners onto tips the quads cut off
      tip_split        where the quads are farther than 1% of the diagonal (or tolerance),
                       make those surface vertices patch corners and run again
      refine           cut the quads still far at thirds in the same map
      patch_rounds     run again with 1.5 and 2 times the automatic patch count
      misfit_split     cut the patches no rectangle fits in two where quads still fold
      fold_rounds      rounds of more quads across patches still folded (default 2)
      smooth           tangential smoothing sweeps, the last pass (default 0: off)
      tolerance        at the default size: more quads while the quads are farther than
                       this fraction of the diagonal (0: off, the default)
      tolerance_rounds how often at most tolerance asks for more quads (default 2)
    Input:
      feature_angle    dihedral angle in degrees above which an edge is a crease (default 60)
      repair           detach non-manifold edges, drop degenerate faces instead of refusing
      weld_eps         weld boundary vertices closer than this fraction of the diagonal
                       (0 to 0.1, default 0)
      weld_all         weld every coincident vertex first (STL soups; see read)
    Run:
      allow_topology_change  keep quads whose topology (genus, boundary loops, connected
                       pieces) differs from their component's, with warning W113 in
                       report["warnings"] (by default an ExtractionError, E603)
      allow_invalid    where no alternative gives a component valid quads, keep its best
                       ones with warning W117 (by default an ExtractionError, E604)
      threads          worker threads at most (0: all cores); the output is the same for any
      quality          measure the quads against the input into report["quality"]
      progress         called as progress(fraction, stage, message) as each stage begins and
                       with each line said: fraction in [0, 1] never going down, stage
                       "prepare", then per component "segment", "layout", "map", "extract",
                       "repair" (repairs run the stages again: reported again), then
                       "quality" and "done"; message the line the command line prints (or
                       "" where a stage begins). Called on the thread that called remesh, with
                       the GIL. An exception it raises (and Ctrl-C) ends the run and is raised
                       from remesh.

    Raises ValueError for a bad array shape or dtype, and isoquad.Error subclasses for what the
    command line refuses: InputError (E003 an option out of its range, E020 an index out of
    range, E1xx the mesh), TopologyError, LayoutError, SolverError, ExtractionError.
    """
    V = _vertices(V, "V")
    F = _faces(F, "F")
    o = _core.RemeshOptions()
    if quads is not None and edge_length is not None:
        raise _refuse("give a quad count or an edge length, not both")
    o.quads = float(quads) if quads is not None else 0.0
    o.edge_length = float(edge_length) if edge_length is not None else 0.0
    o.patches = 0 if patches == "auto" else _count("patches", patches, 1)
    o.seed = _count("seed", seed)
    o.paper_weights = _choice("weights", weights, ("smvc", "mvc")) == "mvc"
    o.relax = str(relax)
    o.segmentation = str(segmentation)
    o.local_corners = _choice("corners", corners, ("global", "local")) == "local"
    o.improve_corners = bool(improve_corners)
    o.feature_angle_deg = float(feature_angle)
    o.repair = bool(repair)
    o.weld_epsilon = float(weld_eps)
    o.weld_all = bool(weld_all)
    if smooth is not None:
        o.smooth = _count("smooth", smooth)
    o.untangle = bool(untangle)
    o.snap = bool(snap)
    o.fold_rounds = _count("fold_rounds", fold_rounds)
    o.split_patches = bool(split_patches)
    o.tip_split = bool(tip_split)
    o.refine = bool(refine)
    o.patch_rounds = bool(patch_rounds)
    o.misfit_split = bool(misfit_split)
    o.tolerance = float(tolerance)
    o.tolerance_rounds = _count("tolerance_rounds", tolerance_rounds)
    o.allow_topology_change = bool(allow_topology_change)
    o.allow_invalid = bool(allow_invalid)
    o.threads = _count("threads", threads)
    o.quality = bool(quality)
    Vq, Q, patch, report = _core.remesh(V, F, o, progress)
    return RemeshResult(Vq, Q, _json.loads(report), patch)


def read(path, repair=False):
    """Read a mesh file (OBJ, OFF, PLY, STL; format from the extension, else the content):
    returns (V, F), V float64 (n, 3) and F int32 (m, k), k the largest face size, shorter faces
    padded with -1 (a triangle mesh is (m, 3)). With repair=True faces with fewer than 3
    distinct vertices are dropped instead of refused. The result's .unshared_vertices is True
    for STL files (pass weld_all=True to remesh). Raises InputError (E001 unreadable, E002
    unknown format, E010-E016 malformed, with file and line)."""
    V, F, unshared = _core.read(str(path), bool(repair))
    return Mesh(V, F, unshared)


def write(path, V, F, patch=None):
    """Write a mesh (OBJ, OFF or binary PLY, from the extension), atomically, coordinates in
    their shortest round-trip form (reading them back is bit-exact). F (m, k) rows end at their
    first -1. patch, one integer per face (e.g. remesh(...).patch), is written as OBJ groups
    `g patch_N` and as the PLY face property `patch`. Raises InputError (E001, E002, E020)."""
    V = _vertices(V, "V")
    F = _faces(F, "F")
    group = _np.zeros(0, dtype=_np.int32) if patch is None else _np.asarray(patch)
    if patch is not None and (group.dtype.kind not in "iu" or group.shape != (F.shape[0],)):
        raise ValueError(f"patch must hold one integer per face ({F.shape[0]}), not "
                         f"shape {group.shape} dtype {group.dtype}")
    _core.write(str(path), V, F, _np.ascontiguousarray(group, dtype=_np.int32))


def quality(V, Q, reference=None):
    """Measure a quad mesh as `isoquad quality --json` does: returns that dictionary (pure
    quad, manifold, oriented, topology, interior valences, scaled Jacobian, angle deviation,
    edge lengths). With reference=(V0, F0), the input surface, also the topology comparison,
    the scaled Jacobians against its normals and the two-sided distances over its bounding-box
    diagonal (hausdorff, mean_distance)."""
    V = _vertices(V, "V")
    Q = _faces(Q, "Q")
    if Q.shape[0] == 0:
        raise ValueError("Q has no faces")
    if reference is None:
        return _json.loads(_core.quality(V, Q, None, None))
    if not isinstance(reference, (tuple, list)) or len(reference) != 2:
        raise ValueError("reference must be a pair (V0, F0)")
    V0 = _vertices(reference[0], "reference V0")
    F0 = _faces(reference[1], "reference F0")
    return _json.loads(_core.quality(V, Q, V0, F0))


def tune_allocator():
    """Make the C library keep freed memory for reuse (glibc's mmap and trim thresholds), as the
    command line does: a process that remeshes often runs up to 15% faster. Process-wide."""
    _core.tune_allocator()
