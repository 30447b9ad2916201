// SPDX-License-Identifier: Apache-2.0
#include "mesh/TetMeshFile.h"

#include <array>
#include <cmath>
#include <fstream>
#include <sstream>
#include <unordered_map>
#include <vector>

#include "io/WholeFile.h"
#include "mesh/SurfaceReader.h"

namespace tissuesim {
namespace {

/// Line-by-line reading with the line number kept for messages.
class LineReader {
 public:
  explicit LineReader(const std::filesystem::path& path) : m_name(path.string()), m_in(path) {
    std::error_code error;
    if (!std::filesystem::is_regular_file(path, error) || !m_in) {
      throw MeshFileError(m_name + ": cannot open the mesh file (missing or not a file)");
    }
    const auto size = std::filesystem::file_size(path, error);
    if (!error && size == 0) throw MeshFileError(m_name + ": the file is empty");
    if (!error && size > kMaxMeshFileBytes) {
      throw MeshFileError(m_name + ": " + std::to_string(size >> 20) +
                          " MiB is beyond the limit of 256 MiB for a mesh file");
    }
  }
  bool next(std::string& line) {
    while (std::getline(m_in, line)) {
      ++m_line;
      if (!line.empty() && line.back() == '\r') line.pop_back();
      for (const unsigned char c : line) {
        if (c < 0x09 || (c > 0x0d && c < 0x20))
          fail("contains binary data; expected an ASCII mesh");
      }
      const auto first = line.find_first_not_of(" \t");
      if (first == std::string::npos || line[first] == '#') continue;
      return true;
    }
    return false;
  }
  std::string require(const char* what) {
    std::string line;
    if (!next(line)) fail(std::string("ended early; expected ") + what);
    return line;
  }
  [[noreturn]] void fail(const std::string& what) const {
    throw MeshFileError(m_name + ":" + std::to_string(m_line) + ": " + what);
  }
  const std::string& name() const { return m_name; }

 private:
  std::string m_name;
  std::ifstream m_in;
  int m_line = 0;
};

template <typename T>
T parse(std::istringstream& in, LineReader& reader, const char* what) {
  T value{};
  if (!(in >> value)) reader.fail(std::string("expected ") + what);
  return value;
}

long long countLine(LineReader& reader, const char* what) {
  std::istringstream in(reader.require(what));
  const long long count = parse<long long>(in, reader, what);
  if (count < 0 || count > 100'000'000) reader.fail(std::string("implausible count for ") + what);
  return count;
}

struct RawMesh {
  std::vector<long long> nodeIds;
  std::vector<Eigen::Vector3d> nodes;
  std::vector<std::array<long long, 4>> tets;  // node ids, not yet indices
  int skipped = 0;
};

void readNodeLine(const std::string& line, LineReader& reader, RawMesh& raw) {
  std::istringstream in(line);
  const auto id = parse<long long>(in, reader, "a node id");
  Eigen::Vector3d p;
  for (int a = 0; a < 3; ++a) p[a] = parse<double>(in, reader, "three node coordinates");
  raw.nodeIds.push_back(id);
  raw.nodes.push_back(p);
}

/// The rest of an element line: a tet's four node ids, or just a count for any other element.
void takeElement(std::istringstream& in, LineReader& reader, bool isTet, RawMesh& raw) {
  if (!isTet) {
    ++raw.skipped;
    return;
  }
  std::array<long long, 4> ids{};
  for (auto& id : ids) id = parse<long long>(in, reader, "four tet node ids");
  raw.tets.push_back(ids);
}

void readGmsh1(LineReader& reader, RawMesh& raw) {
  const long long nodes = countLine(reader, "the node count");
  for (long long i = 0; i < nodes; ++i) readNodeLine(reader.require("a node"), reader, raw);
  if (reader.require("$ENDNOD").rfind("$ENDNOD", 0) != 0) reader.fail("expected $ENDNOD");
  if (reader.require("$ELM").rfind("$ELM", 0) != 0) reader.fail("expected $ELM");
  const long long elements = countLine(reader, "the element count");
  for (long long e = 0; e < elements; ++e) {
    std::istringstream in(reader.require("an element"));
    parse<long long>(in, reader, "an element id");
    const int type = parse<int>(in, reader, "an element type");
    parse<long long>(in, reader, "a physical region");
    parse<long long>(in, reader, "an elementary region");
    const int count = parse<int>(in, reader, "a node count");
    // Not trusted to size anything: the ids are read one by one, as many as the line holds.
    if (count < 0) reader.fail("a negative node count");
    std::vector<long long> ids;
    for (int k = 0; k < count; ++k) ids.push_back(parse<long long>(in, reader, "element node ids"));
    if (type == 4 && count == 4) {
      raw.tets.push_back({ids[0], ids[1], ids[2], ids[3]});
    } else {
      ++raw.skipped;
    }
  }
}

void readGmsh2(LineReader& reader, RawMesh& raw) {
  std::string line;
  while (reader.next(line)) {
    if (line.rfind("$Nodes", 0) == 0) {
      const long long nodes = countLine(reader, "the node count");
      for (long long i = 0; i < nodes; ++i) readNodeLine(reader.require("a node"), reader, raw);
    } else if (line.rfind("$Elements", 0) == 0) {
      const long long elements = countLine(reader, "the element count");
      for (long long e = 0; e < elements; ++e) {
        std::istringstream in(reader.require("an element"));
        parse<long long>(in, reader, "an element id");
        const int type = parse<int>(in, reader, "an element type");
        const int tags = parse<int>(in, reader, "a tag count");
        for (int t = 0; t < tags; ++t) parse<long long>(in, reader, "element tags");
        takeElement(in, reader, type == 4, raw);
      }
    }
  }
}

void readGmsh4(LineReader& reader, RawMesh& raw) {
  std::string line;
  while (reader.next(line)) {
    if (line.rfind("$Nodes", 0) == 0) {
      std::istringstream header(reader.require("the $Nodes header"));
      const auto blocks = parse<long long>(header, reader, "the entity block count");
      for (long long b = 0; b < blocks; ++b) {
        std::istringstream block(reader.require("a node block header"));
        parse<int>(block, reader, "an entity dimension");
        parse<int>(block, reader, "an entity tag");
        const int parametric = parse<int>(block, reader, "the parametric flag");
        const auto count = parse<long long>(block, reader, "a node count");
        if (parametric != 0) reader.fail("parametric nodes are not supported");
        if (count < 0) reader.fail("a negative node count");
        // The count is not trusted to size anything: tags are kept as their lines are read.
        std::vector<long long> tags;
        for (long long k = 0; k < count; ++k) {
          std::istringstream in(reader.require("a node tag"));
          tags.push_back(parse<long long>(in, reader, "a node tag"));
        }
        for (const long long tag : tags) {
          std::istringstream in(reader.require("node coordinates"));
          Eigen::Vector3d p;
          for (int a = 0; a < 3; ++a) p[a] = parse<double>(in, reader, "three node coordinates");
          raw.nodeIds.push_back(tag);
          raw.nodes.push_back(p);
        }
      }
    } else if (line.rfind("$Elements", 0) == 0) {
      std::istringstream header(reader.require("the $Elements header"));
      const auto blocks = parse<long long>(header, reader, "the entity block count");
      for (long long b = 0; b < blocks; ++b) {
        std::istringstream block(reader.require("an element block header"));
        parse<int>(block, reader, "an entity dimension");
        parse<int>(block, reader, "an entity tag");
        const int type = parse<int>(block, reader, "an element type");
        const auto count = parse<long long>(block, reader, "an element count");
        for (long long e = 0; e < count; ++e) {
          std::istringstream in(reader.require("an element"));
          parse<long long>(in, reader, "an element tag");
          takeElement(in, reader, type == 4, raw);
        }
      }
    }
  }
}

void readTetgen(const std::filesystem::path& path, RawMesh& raw) {
  std::filesystem::path nodePath = path;
  std::filesystem::path elePath = path;
  nodePath.replace_extension(".node");
  elePath.replace_extension(".ele");
  LineReader nodes(nodePath);
  std::istringstream header(nodes.require("the .node header"));
  const auto count = parse<long long>(header, nodes, "the point count");
  const int dimension = parse<int>(header, nodes, "the dimension");
  if (dimension != 3) nodes.fail("dimension " + std::to_string(dimension) + "; expected 3");
  for (long long i = 0; i < count; ++i) readNodeLine(nodes.require("a point"), nodes, raw);
  LineReader elements(elePath);
  std::istringstream eleHeader(elements.require("the .ele header"));
  const auto tets = parse<long long>(eleHeader, elements, "the tet count");
  const int perTet = parse<int>(eleHeader, elements, "nodes per tet");
  if (perTet != 4 && perTet != 10) elements.fail("nodes per tet must be 4 or 10");
  for (long long t = 0; t < tets; ++t) {
    std::istringstream in(elements.require("a tet"));
    parse<long long>(in, elements, "a tet index");
    takeElement(in, elements, true, raw);  // corner nodes only for 10-node tets
  }
}

TetMesh assemble(const RawMesh& raw, const std::string& name, double metresPerUnit) {
  std::unordered_map<long long, int> index;
  TetMesh mesh;
  mesh.nodes_m.resize(3, static_cast<Eigen::Index>(raw.nodes.size()));
  for (std::size_t i = 0; i < raw.nodes.size(); ++i) {
    if (!index.emplace(raw.nodeIds[i], static_cast<int>(i)).second) {
      throw MeshFileError(name + ": node id " + std::to_string(raw.nodeIds[i]) + " appears twice");
    }
    if (!raw.nodes[i].allFinite()) {
      throw MeshFileError(name + ": node " + std::to_string(raw.nodeIds[i]) +
                          " has a coordinate that is not finite");
    }
    mesh.nodes_m.col(static_cast<Eigen::Index>(i)) = raw.nodes[i] * metresPerUnit;
    if (mesh.nodes_m.col(static_cast<Eigen::Index>(i)).cwiseAbs().maxCoeff() > 100.0) {
      throw MeshFileError(name + ": node " + std::to_string(raw.nodeIds[i]) +
                          " lies beyond 100 m from the origin after scaling (check the units)");
    }
  }
  if (raw.tets.empty()) {
    throw MeshFileError(name + ": the mesh has no tetrahedra" +
                        (raw.skipped > 0 ? " (only " + std::to_string(raw.skipped) +
                                               " other elements: a surface mesh?)"
                                         : ""));
  }
  mesh.tets.resize(4, static_cast<Eigen::Index>(raw.tets.size()));
  for (std::size_t t = 0; t < raw.tets.size(); ++t) {
    for (int k = 0; k < 4; ++k) {
      const auto found = index.find(raw.tets[t][static_cast<std::size_t>(k)]);
      if (found == index.end()) {
        throw MeshFileError(name + ": tet " + std::to_string(t) + " refers to node " +
                            std::to_string(raw.tets[t][static_cast<std::size_t>(k)]) +
                            ", which the file does not define");
      }
      mesh.tets(k, static_cast<Eigen::Index>(t)) = found->second;
    }
  }
  return mesh;
}

}  // namespace

bool isTetMeshFile(const std::filesystem::path& path) {
  const std::string extension = path.extension().string();
  return extension == ".msh" || extension == ".node" || extension == ".ele";
}

void checkTetOrientation(TetMesh& mesh, const std::string& name, TetMeshReadReport* report) {
  try {
    validateTetMesh(mesh, name);
  } catch (const std::invalid_argument& error) {
    throw MeshFileError(error.what());
  }
  const TetQualityReport quality = inspectTets(mesh, 0.0);
  for (Eigen::Index t = 0; t < mesh.tetCount(); ++t) {
    if (signedTetVolume(mesh.nodes_m, mesh.tets, t) == 0.0) {
      throw MeshFileError(name + ": tet " + std::to_string(t) + " has zero volume");
    }
  }
  if (quality.invertedTets.empty()) return;
  if (static_cast<Eigen::Index>(quality.invertedTets.size()) == mesh.tetCount()) {
    mesh.tets.row(2).swap(mesh.tets.row(3));
    if (report != nullptr) report->wasReoriented = true;
    return;
  }
  std::string list;
  for (std::size_t i = 0; i < std::min<std::size_t>(5, quality.invertedTets.size()); ++i) {
    list += (i == 0 ? "" : ", ") + std::to_string(quality.invertedTets[i]);
  }
  throw MeshFileError(name + ": " + std::to_string(quality.invertedTets.size()) + " of " +
                      std::to_string(mesh.tetCount()) +
                      " tets are inverted (the mesh is folded), e.g. tets " + list);
}

TetMesh readTetMesh(const std::filesystem::path& path, double metresPerUnit,
                    TetMeshReadReport* report) {
  const std::string name = path.string();
  RawMesh raw;
  std::string format;
  const std::string extension = path.extension().string();
  if (extension == ".node" || extension == ".ele") {
    readTetgen(path, raw);
    format = "tetgen";
  } else if (extension == ".msh") {
    LineReader reader(path);
    const std::string first = reader.require("a Gmsh header");
    if (first.rfind("$NOD", 0) == 0) {
      readGmsh1(reader, raw);
      format = "gmsh 1";
    } else if (first.rfind("$MeshFormat", 0) == 0) {
      std::istringstream in(reader.require("the format version"));
      const auto version = parse<double>(in, reader, "the format version");
      const int fileType = parse<int>(in, reader, "the file type");
      if (fileType != 0) reader.fail("binary Gmsh files are not supported; save as ASCII");
      if (version >= 2.0 && version < 3.0) {
        readGmsh2(reader, raw);
        format = "gmsh 2.2";
      } else if (version >= 4.0 && version < 5.0) {
        readGmsh4(reader, raw);
        format = "gmsh 4.1";
      } else {
        reader.fail("Gmsh format " + std::to_string(version) + " is not supported (1, 2.2, 4.1)");
      }
    } else {
      reader.fail("not a Gmsh file: expected $MeshFormat or $NOD");
    }
  } else {
    throw MeshFileError(name + ": unknown tet mesh extension '" + extension +
                        "'; expected .msh, .node/.ele, .vtk or .vtu");
  }
  TetMesh mesh = assemble(raw, name, metresPerUnit);
  TetMeshReadReport local;
  local.skippedElements = raw.skipped;
  local.format = format;
  checkTetOrientation(mesh, name, &local);
  if (report != nullptr) *report = local;
  return mesh;
}

void writeGmsh(const std::filesystem::path& path, const TetMesh& mesh) {
  std::ostringstream out;
  out << "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$Nodes\n" << mesh.nodeCount() << "\n";
  out.precision(17);
  for (Eigen::Index i = 0; i < mesh.nodeCount(); ++i) {
    out << i + 1 << ' ' << mesh.nodes_m(0, i) << ' ' << mesh.nodes_m(1, i) << ' '
        << mesh.nodes_m(2, i) << '\n';
  }
  out << "$EndNodes\n$Elements\n" << mesh.tetCount() << "\n";
  for (Eigen::Index t = 0; t < mesh.tetCount(); ++t) {
    out << t + 1 << " 4 2 1 1";
    for (int k = 0; k < 4; ++k) out << ' ' << mesh.tets(k, t) + 1;
    out << '\n';
  }
  out << "$EndElements\n";
  try {
    writeWholeFile(path, out.str());
  } catch (const std::runtime_error& error) {
    throw MeshFileError(error.what());
  }
}

}  // namespace tissuesim
