// puffbake mesh: a generated puff, or a normalized copy of a mesh file, as a mesh file.
#include <cstdio>

#include <cli/app.h>
#include <puff/mesh/mesh.h>

#include "commands.h"

namespace puff::app {

CLI::App* addMeshCommand(CLI::App& app, Options& o, GeneratorFlags& generator) {
  CLI::App* cmd =
      app.add_subcommand("mesh", "Write a generated puff, or a normalized copy of a mesh file, as OBJ/OFF/PLY/STL");
  cmd->add_option("mesh", o.inputs,
                  std::string("Mesh file to normalize: ") + mesh::kMeshFormatsRead + " (or use --generate)");
  generator.add(*cmd, false);
  cmd->add_option("-o,--out", o.meshOut, "Output mesh file; the extension picks the format")->required();
  cmd->add_flag("-q,--quiet", o.quiet, "Print errors only");
  return cmd;
}

int runMesh(const Options& o) {
  if (o.meshOut.empty()) {
    cli::printError("mesh: -o FILE is required");
    return 2;
  }
  if (o.inputs.size() + (o.generator ? 1 : 0) != 1) {
    cli::printError("mesh: give exactly one mesh file or --generate KIND");
    return 2;
  }
  std::optional<bake::GeneratorSpec> gen = o.generator;
  if (gen) gen->count = 1;
  auto sources = bake::loadSources(o.inputs, gen);
  if (!sources) {
    cli::printError(sources.error());
    return 1;
  }
  const mesh::TriMesh& m = sources->front().mesh;
  if (auto r = mesh::saveMesh(m, o.meshOut); !r) {
    cli::printError(r.error());
    return 1;
  }
  if (!o.quiet) {
    std::printf("%s: wrote %s (%zu faces, %zu vertices, unit bounding sphere)\n", cli::name(), o.meshOut.c_str(),
                m.faceCount(), m.positions.size());
  }
  return 0;
}

}  // namespace puff::app
