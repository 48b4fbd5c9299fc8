// isoquad/quality.hpp: the quality report of plain arrays, as `isoquad quality --json` prints it.
#include <nlohmann/json.hpp>
#include <optional>

#include "io/mesh_arrays.hpp"
#include "io/report_json.hpp"
#include "isoquad/error.hpp"
#include "isoquad/quality.hpp"
#include "metrics/quality.hpp"

namespace isoquad {

std::string quality_json(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F,
                         const Eigen::MatrixXd* reference_V, const Eigen::MatrixXi* reference_F) {
  const PolyMesh quads = poly_mesh_from_arrays(V, F);
  if (quads.num_faces() == 0)
    throw Error(ErrorKind::invalid_input, "E020", "the quad mesh has no faces");
  std::optional<PolyMesh> reference;
  if (reference_V && reference_F) reference = poly_mesh_from_arrays(*reference_V, *reference_F);
  const nlohmann::json j = measure_quality(quads, reference ? &*reference : nullptr);
  return j.dump(2);
}

}  // namespace isoquad
