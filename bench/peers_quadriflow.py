"""QuadriFlow inside Blender, for bench/peers (run by it, not by hand):

    blender -b --factory-startup -P bench/peers_quadriflow.py -- IN.obj OUT.obj QUADS RESULT.json

Imports IN.obj as it is (no axis conversion), runs Blender's QuadriFlow remesh operator with a
face target of QUADS (no symmetry, sharp edges and boundaries kept: what isoquad keeps), exports
the quads as OUT.obj (same axes), and writes RESULT.json: the operator's own time (the remeshing
alone), the process's peak resident memory before and after it, the quads, and an error if the
operator failed. Blender's exit status stays 0 either way; bench/peers reads RESULT.json.
"""
import json
import resource
import sys
import time

import bpy


def peak_rss_bytes():
    return resource.getrusage(resource.RUSAGE_SELF).ru_maxrss * 1024  # KiB on Linux


def main(src, dst, quads, result_path):
    result = {"quads_asked": quads}
    bpy.ops.wm.read_factory_settings(use_empty=True)
    bpy.ops.wm.obj_import(filepath=src, forward_axis="Y", up_axis="Z")
    obj = bpy.context.selected_objects[0]
    bpy.context.view_layer.objects.active = obj
    result["input_faces"] = len(obj.data.polygons)
    result["peak_rss_before_bytes"] = peak_rss_bytes()
    t0 = time.perf_counter()
    try:
        # Called from Python the operator runs to the end before it returns (no job).
        status = bpy.ops.object.quadriflow_remesh(
            mode="FACES", target_faces=quads, use_mesh_symmetry=False, use_preserve_sharp=True,
            use_preserve_boundary=True, seed=0)
        result["status"] = sorted(status)
    except RuntimeError as e:  # the operator's error report, e.g. a non-manifold input
        result["error"] = str(e).strip()
    result["remesh_seconds"] = time.perf_counter() - t0
    result["peak_rss_bytes"] = peak_rss_bytes()
    obj = bpy.context.view_layer.objects.active
    result["quads"] = len(obj.data.polygons)
    if "error" not in result and result.get("status") != ["FINISHED"]:
        result["error"] = f"operator returned {result.get('status')}"
    if "error" not in result:
        bpy.ops.wm.obj_export(filepath=dst, forward_axis="Y", up_axis="Z",
                              export_materials=False, export_normals=False, export_uv=False)
    with open(result_path, "w") as f:
        json.dump(result, f)


if __name__ == "__main__":
    args = sys.argv[sys.argv.index("--") + 1:]
    main(args[0], args[1], int(args[2]), args[3])
