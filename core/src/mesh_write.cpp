// PLY and OBJ + MTL mesh writers. Written here rather than with VTK because
// VTK 9.1's vtkPLYWriter writes colours but no other vertex property (the
// label), and its vtkOBJWriter has no materials (vtkOBJExporter would need a
// render window). Both formats are plain and fully specified; the tests read
// the files back with VTK's and PCL's readers and with assimp.
#include <algorithm>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <ostream>
#include <string>

#include "lom/atomic_file.hpp"
#include "lom/error.hpp"
#include "lom/export.hpp"
#include "lom/height_colours.hpp"

namespace lom {

namespace {

size_t countTriangles(const std::vector<SurfaceMesh>& meshes) {
  size_t n = 0;
  for (const auto& m : meshes) n += m.triangles.size();
  return n;
}

void requireTriangles(const std::vector<SurfaceMesh>& meshes, const std::filesystem::path& path) {
  if (countTriangles(meshes) == 0)
    throw Error(path.string(), "mesh", "at least one triangle to write", "an empty surface");
}

// As the studio and `render` shade them: mesh viewers shade faces too, and
// the background's black (VOC palette) would hide every shape.
Rgb colorOf(const LabelSet& labels, int label) {
  return labels.contains(label) ? shadedLabelColour(labels, label) : vocColor(label);
}

std::string nameOf(const LabelSet& labels, int label) {
  return labels.contains(label) ? labels.at(label).name : "label_" + std::to_string(label);
}

// Little-endian regardless of the host, as the header says.
void putU32(std::string& out, std::uint32_t v) {
  for (int i = 0; i < 4; ++i) out.push_back(static_cast<char>((v >> (8 * i)) & 0xff));
}
void putF32(std::string& out, float f) {
  std::uint32_t bits;
  std::memcpy(&bits, &f, sizeof bits);
  putU32(out, bits);
}

std::string number(double value) {
  char buffer[32];
  std::snprintf(buffer, sizeof buffer, "%.9g", value);
  return buffer;
}

}  // namespace

void writeMeshesPly(const std::vector<SurfaceMesh>& meshes, const LabelSet& labels,
                    const std::filesystem::path& path, const std::string& frame) {
  requireTriangles(meshes, path);
  constexpr size_t kVertexBytes = 3 * 4 + 3 + 4;
  std::string vertices;
  for (const auto& m : meshes) {
    const Rgb color = colorOf(labels, m.label);
    for (const auto& v : m.vertices) {
      putF32(vertices, static_cast<float>(v.x()));
      putF32(vertices, static_cast<float>(v.y()));
      putF32(vertices, static_cast<float>(v.z()));
      for (const std::uint8_t c : color) vertices.push_back(static_cast<char>(c));
      putU32(vertices, static_cast<std::uint32_t>(m.label));
    }
  }
  const size_t vertex_count = vertices.size() / kVertexBytes;
  // Some readers (assimp 5.2) skip white space after "end_header" even in
  // binary files, eating the first data byte: start with a vertex whose first
  // byte is not white space (vertex 0 and that one trade places).
  const auto isSpace = [](char c) { return c == ' ' || (c >= '\t' && c <= '\r'); };
  std::uint32_t first = 0;
  while (first < vertex_count && isSpace(vertices[first * kVertexBytes])) ++first;
  if (first == vertex_count) first = 0;
  if (first != 0)
    std::swap_ranges(vertices.begin(), vertices.begin() + kVertexBytes,
                     vertices.begin() + static_cast<std::ptrdiff_t>(first * kVertexBytes));
  const auto place = [first](std::uint32_t i) { return i == first ? 0u : i == 0 ? first : i; };

  writeFileAtomically(path, [&](std::ostream& out) {
    out << "ply\nformat binary_little_endian 1.0\n"
        << "comment labeloctomap voxel surface; vertex label = label id\n";
    if (!frame.empty()) out << "comment " << singleLineText(frame) << "\n";
    for (const auto& m : meshes)
      out << "comment label " << m.label << " " << singleLineText(nameOf(labels, m.label)) << "\n";
    out << "element vertex " << vertex_count << "\n"
        << "property float x\nproperty float y\nproperty float z\n"
        << "property uchar red\nproperty uchar green\nproperty uchar blue\n"
        << "property uint label\n"
        << "element face " << countTriangles(meshes) << "\n"
        << "property list uchar int vertex_indices\nend_header\n";
    out.write(vertices.data(), static_cast<std::streamsize>(vertices.size()));
    std::string block;
    std::uint32_t offset = 0;
    for (const auto& m : meshes) {
      block.clear();
      for (const auto& t : m.triangles) {
        block.push_back(3);
        for (const std::uint32_t i : t) putU32(block, place(offset + i));
      }
      out.write(block.data(), static_cast<std::streamsize>(block.size()));
      offset += static_cast<std::uint32_t>(m.vertices.size());
    }
  });
}

void writeMeshesObj(const std::vector<SurfaceMesh>& meshes, const LabelSet& labels,
                    const std::filesystem::path& obj_path, const std::filesystem::path& mtl_path,
                    const std::string& frame) {
  requireTriangles(meshes, obj_path);
  // Material and object names: "08_creativity_chenille_stems" (no spaces in OBJ names).
  const auto materialOf = [&](int label) {
    return labels.contains(label) ? labelFileStem(labels.at(label), labels.size())
                                  : "label_" + std::to_string(label);
  };
  // Both files are complete before either replaces an old one: an old OBJ is
  // never left beside a new MTL (or the other way round).
  StagedFiles files;
  files.add(
      mtl_path,
      [&](std::ostream& out) {
        out << "# labeloctomap label materials\n";
        for (const auto& m : meshes) {
          const Rgb c = colorOf(labels, m.label);
          const std::string kd =
              number(c[0] / 255.0) + " " + number(c[1] / 255.0) + " " + number(c[2] / 255.0);
          out << "\nnewmtl " << materialOf(m.label) << "\nKa " << kd << "\nKd " << kd
              << "\nKs 0 0 0\nd 1\nillum 1\n";
        }
      },
      false);
  files.add(
      obj_path,
      [&](std::ostream& out) {
        out << "# labeloctomap voxel surface, one object per label\n";
        if (!frame.empty()) out << "# " << singleLineText(frame) << "\n";
        out << "mtllib " << mtl_path.filename().string() << "\n";
        size_t offset = 1;  // OBJ indices start at 1
        for (const auto& m : meshes) {
          out << "\no " << materialOf(m.label) << "\nusemtl " << materialOf(m.label) << "\n";
          for (const auto& v : m.vertices)
            out << "v " << number(v.x()) << " " << number(v.y()) << " " << number(v.z()) << "\n";
          for (const auto& t : m.triangles)
            out << "f " << offset + t[0] << " " << offset + t[1] << " " << offset + t[2] << "\n";
          offset += m.vertices.size();
        }
      },
      false);
  files.commit();
}

}  // namespace lom
