// isoquad._core: the public C++ API (include/isoquad/) for Python. The package's __init__.py
// wraps it with keyword arguments, checks and docstrings; this file only converts and releases
// the GIL while the library works.
#include <pybind11/eigen.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <optional>
#include <string>

#include "isoquad/error.hpp"
#include "isoquad/io.hpp"
#include "isoquad/quality.hpp"
#include "isoquad/remesh.hpp"
#include "isoquad/version.hpp"

namespace py = pybind11;

namespace {

using RowMatrixXd = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;
using RowMatrixXi = Eigen::Matrix<int, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;

// The exception class of the package (isoquad.InputError, ...) for an error kind, looked up
// when it is raised: the package defines them in Python, with their attributes.
const char* class_name(isoquad::ErrorKind kind) {
  switch (kind) {
    case isoquad::ErrorKind::invalid_input:
      return "InputError";
    case isoquad::ErrorKind::unsupported_topology:
      return "TopologyError";
    case isoquad::ErrorKind::layout:
      return "LayoutError";
    case isoquad::ErrorKind::solver:
      return "SolverError";
    case isoquad::ErrorKind::extraction:
      return "ExtractionError";
    case isoquad::ErrorKind::internal:
      return "InternalError";
  }
  return "Error";
}

void raise_python_error(const isoquad::Error& e) {
  const py::object cls = py::module_::import("isoquad").attr(class_name(e.kind()));
  const isoquad::ErrorContext& at = e.context();
  const py::object error = cls(
      e.what(), e.code(), e.exit_status(), at.file,
      at.line >= 0 ? py::object(py::int_(at.line)) : py::object(py::none()), at.vertices, at.faces);
  PyErr_SetObject(cls.ptr(), error.ptr());
}

// Thrown through the library when the Python progress callback raised (or a signal such as
// Ctrl-C arrived): the Python exception is raised again once the run has unwound.
struct CallbackRaised {};

py::tuple py_remesh(const RowMatrixXd& V, const RowMatrixXi& F,
                    const isoquad::RemeshOptions& options, const py::object& progress) {
  const Eigen::MatrixXd v = V;
  const Eigen::MatrixXi f = F;
  std::optional<py::error_already_set> raised;
  const isoquad::ProgressCallback callback = [&](const isoquad::Progress& p) {
    py::gil_scoped_acquire gil;
    try {
      if (!progress.is_none()) progress(p.fraction, p.stage, p.message);
      if (PyErr_CheckSignals() != 0) throw py::error_already_set();
    } catch (py::error_already_set& e) {
      raised.emplace(std::move(e));
      throw CallbackRaised{};
    }
  };
  isoquad::RemeshResult r;
  try {
    py::gil_scoped_release release;
    r = isoquad::remesh(v, f, options, callback);
  } catch (const CallbackRaised&) {
    throw std::move(*raised);
  }
  return py::make_tuple(RowMatrixXd(r.V), RowMatrixXi(r.Q), Eigen::VectorXi(r.patch), r.report);
}

py::tuple py_read(const std::string& path, bool drop_degenerate_faces) {
  isoquad::MeshArrays m;
  {
    py::gil_scoped_release release;
    m = isoquad::read_mesh_arrays(path, drop_degenerate_faces);
  }
  return py::make_tuple(RowMatrixXd(m.V), RowMatrixXi(m.F), m.unshared_vertices);
}

void py_write(const std::string& path, const RowMatrixXd& V, const RowMatrixXi& F,
              const Eigen::VectorXi& group) {
  const Eigen::MatrixXd v = V;
  const Eigen::MatrixXi f = F;
  py::gil_scoped_release release;
  isoquad::write_mesh_arrays(path, v, f, group);
}

std::string py_quality(const RowMatrixXd& V, const RowMatrixXi& F,
                       const std::optional<RowMatrixXd>& reference_V,
                       const std::optional<RowMatrixXi>& reference_F) {
  const Eigen::MatrixXd v = V;
  const Eigen::MatrixXi f = F;
  std::optional<Eigen::MatrixXd> rv;
  std::optional<Eigen::MatrixXi> rf;
  if (reference_V && reference_F) rv = *reference_V, rf = *reference_F;
  py::gil_scoped_release release;
  return isoquad::quality_json(v, f, rv ? &*rv : nullptr, rf ? &*rf : nullptr);
}

}  // namespace

PYBIND11_MODULE(_core, m) {
  m.doc() = "isoquad's C++ library; use the isoquad package, which wraps it.";
  py::register_exception_translator([](std::exception_ptr p) {
    try {
      if (p) std::rethrow_exception(p);
    } catch (const isoquad::Error& e) {
      raise_python_error(e);
    }
  });
  py::class_<isoquad::RemeshOptions> o(m, "RemeshOptions");
  o.def(py::init<>());
#define ISOQUAD_FIELD(name) o.def_readwrite(#name, &isoquad::RemeshOptions::name)
  ISOQUAD_FIELD(patches);
  ISOQUAD_FIELD(edge_length);
  ISOQUAD_FIELD(quads);
  ISOQUAD_FIELD(seed);
  ISOQUAD_FIELD(paper_weights);
  ISOQUAD_FIELD(relax);
  ISOQUAD_FIELD(segmentation);
  ISOQUAD_FIELD(local_corners);
  ISOQUAD_FIELD(improve_corners);
  ISOQUAD_FIELD(feature_angle_deg);
  ISOQUAD_FIELD(repair);
  ISOQUAD_FIELD(weld_epsilon);
  ISOQUAD_FIELD(weld_all);
  ISOQUAD_FIELD(smooth);
  ISOQUAD_FIELD(untangle);
  ISOQUAD_FIELD(snap);
  ISOQUAD_FIELD(fold_rounds);
  ISOQUAD_FIELD(split_patches);
  ISOQUAD_FIELD(tip_split);
  ISOQUAD_FIELD(refine);
  ISOQUAD_FIELD(patch_rounds);
  ISOQUAD_FIELD(misfit_split);
  ISOQUAD_FIELD(tolerance);
  ISOQUAD_FIELD(tolerance_rounds);
  ISOQUAD_FIELD(allow_topology_change);
  ISOQUAD_FIELD(allow_invalid);
  ISOQUAD_FIELD(quality);
  ISOQUAD_FIELD(threads);
#undef ISOQUAD_FIELD
  m.def("remesh", &py_remesh, py::arg("V"), py::arg("F"), py::arg("options"), py::arg("progress"));
  m.def("read", &py_read, py::arg("path"), py::arg("drop_degenerate_faces"));
  m.def("write", &py_write, py::arg("path"), py::arg("V"), py::arg("F"), py::arg("group"));
  m.def("quality", &py_quality, py::arg("V"), py::arg("F"), py::arg("reference_V"),
        py::arg("reference_F"));
  m.def("version", &isoquad::version);
  m.def("tune_allocator", &isoquad::tune_allocator);
}
