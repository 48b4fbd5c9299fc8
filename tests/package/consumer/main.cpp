// consumer IN OUT QUADS: remeshes IN into OUT through the installed headers only, and checks
// what the public API promises: progress that never goes down and ends at 1, valid quads.
#include <isoquad/error.hpp>
#include <isoquad/io.hpp>
#include <isoquad/quality.hpp>
#include <isoquad/remesh.hpp>
#include <isoquad/version.hpp>

#include <cstdio>
#include <cstdlib>
#include <string>

int main(int argc, char** argv) {
  if (argc != 4) {
    std::fprintf(stderr, "usage: consumer IN OUT QUADS\n");
    return 2;
  }
  try {
    const isoquad::MeshArrays in = isoquad::read_mesh_arrays(argv[1]);
    isoquad::RemeshOptions options;
    options.quads = std::atof(argv[3]);
    options.weld_all = in.unshared_vertices;
    double last = 0;
    bool monotone = true;
    const isoquad::RemeshResult r =
        isoquad::remesh(in.V, in.F, options, [&](const isoquad::Progress& p) {
          monotone = monotone && p.fraction >= last;
          last = p.fraction;
        });
    isoquad::write_mesh_arrays(argv[2], r.V, r.Q, r.patch);
    const std::string quality = isoquad::quality_json(r.V, r.Q, &in.V, &in.F);
    std::printf("isoquad %s: %ld quads\n", isoquad::version(), static_cast<long>(r.Q.rows()));
    if (!monotone || last != 1 || quality.find("\"pure_quad\": true") == std::string::npos) {
      std::fprintf(stderr, "consumer: progress %s, ending at %g; quality %s\n",
                   monotone ? "monotone" : "went down", last, quality.c_str());
      return 1;
    }
  } catch (const isoquad::Error& e) {
    std::fprintf(stderr, "consumer: %s (exit status %d)\n", e.what(), e.exit_status());
    return e.exit_status();
  }
  return 0;
}
