#include <cstring>
#include <fstream>
#include <sstream>

#include "base/errors.h"
#include "base/file_names.h"
#include "io/mesh_io.h"
#include "io/mesh_3mf.h"

namespace frep {

namespace {

std::string slurp(const std::string& path) {
  requireRegularFile(path, "a mesh file");  // a FIFO would block, a folder reads as empty
  std::ifstream in(path, std::ios::binary);
  if (!in) throw FileError(displayName(path) + ": cannot open the file");
  std::stringstream ss;
  ss << in.rdbuf();
  if (in.bad()) throw FileError(displayName(path) + ": read error");
  return ss.str();
}

// Adds a polygon as a fan of triangles after checking its indices.
void addPolygon(TriangleMesh& m, const std::vector<long long>& ids, const std::string& where) {
  if (ids.size() < 3) throw FileError(where + ": a face needs at least 3 vertices");
  for (long long id : ids)
    if (id < 0 || static_cast<std::size_t>(id) >= m.positions.size())
      throw FileError(where + ": vertex index " + std::to_string(id) + " out of range (" +
                      std::to_string(m.positions.size()) + " vertices)");
  for (std::size_t i = 1; i + 1 < ids.size(); ++i)
    m.triangles.push_back({static_cast<std::uint32_t>(ids[0]), static_cast<std::uint32_t>(ids[i]),
                           static_cast<std::uint32_t>(ids[i + 1])});
}

TriangleMesh readStl(const std::string& path, const std::string& data) {
  TriangleMesh m;
  if (data.size() >= 84) {
    std::uint32_t n = 0;
    std::memcpy(&n, data.data() + 80, 4);
    if (data.size() == 84 + 50ull * n) {
      m.positions.reserve(3ull * n);
      for (std::uint32_t i = 0; i < n; ++i) {
        const char* rec = data.data() + 84 + 50ull * i + 12;
        for (int c = 0; c < 3; ++c) {
          Vec3f p;
          std::memcpy(p.data(), rec + 12 * c, 12);
          m.positions.push_back(p);
        }
        const std::uint32_t b = 3 * i;
        m.triangles.push_back({b, b + 1, b + 2});
      }
      return m;
    }
  }
  if (data.compare(0, 5, "solid") != 0)
    throw FileError(displayName(path) + ": not an STL file (binary size does not match its triangle count, "
                           "and it does not start with 'solid')");
  // ASCII STL, read strictly: a garbage file is bad input (exit 2), not an empty mesh that
  // the check would call "not printable".
  std::istringstream in(data);
  std::string line;
  std::size_t lineNo = 0, inLoop = 0;
  bool ended = false, loop = false;
  while (std::getline(in, line)) {
    ++lineNo;
    std::istringstream ls(line);
    std::string word;
    if (!(ls >> word)) continue;
    const std::string where = displayName(path) + ":" + std::to_string(lineNo);
    if (ended) throw FileError(where + ": text after 'endsolid'");
    if (lineNo == 1 && word == "solid") continue;
    if (word == "facet") {
      std::string normal;
      float n[3];
      if (!(ls >> normal >> n[0] >> n[1] >> n[2]) || normal != "normal")
        throw FileError(where + ": ASCII STL 'facet' needs 'normal' and three numbers");
    } else if (word == "outer") {
      std::string l;
      if (!(ls >> l) || l != "loop") throw FileError(where + ": ASCII STL expects 'outer loop'");
      loop = true;
      inLoop = 0;
    } else if (word == "vertex") {
      Vec3f p;
      if (!loop || !(ls >> p[0] >> p[1] >> p[2]))
        throw FileError(where + ": ASCII STL 'vertex' needs three numbers inside 'outer loop'");
      m.positions.push_back(p);
      ++inLoop;
    } else if (word == "endloop") {
      if (!loop || inLoop != 3)
        throw FileError(where + ": ASCII STL facet with " + std::to_string(inLoop) +
                        " vertices; a facet has 3");
      const std::uint32_t b = static_cast<std::uint32_t>(m.positions.size() - 3);
      m.triangles.push_back({b, b + 1, b + 2});
      loop = false;
    } else if (word == "endfacet") {
      if (loop) throw FileError(where + ": 'endfacet' before 'endloop'");
    } else if (word == "endsolid") {
      ended = true;
    } else {
      throw FileError(where + ": unexpected '" + word.substr(0, 40) +
                      "' in an ASCII STL (facet, outer loop, vertex, endloop, endfacet, "
                      "endsolid)");
    }
  }
  if (!ended) throw FileError(displayName(path) + ": ASCII STL ends without 'endsolid' (a truncated file?)");
  return m;
}

TriangleMesh readObj(const std::string& path, const std::string& data) {
  TriangleMesh m;
  std::istringstream in(data);
  std::string line;
  std::size_t lineNo = 0;
  while (std::getline(in, line)) {
    ++lineNo;
    std::istringstream ls(line);
    std::string tag;
    ls >> tag;
    const std::string where = displayName(path) + ":" + std::to_string(lineNo);
    if (tag == "v") {
      Vec3f p;
      if (!(ls >> p[0] >> p[1] >> p[2])) throw FileError(where + ": 'v' needs three numbers");
      m.positions.push_back(p);
    } else if (tag == "f") {
      std::vector<long long> ids;
      std::string tok;
      while (ls >> tok) {
        long long id = 0;
        try {
          id = std::stoll(tok.substr(0, tok.find('/')));
        } catch (...) {
          throw FileError(where + ": bad face index '" + tok + "'");
        }
        ids.push_back(id < 0 ? static_cast<long long>(m.positions.size()) + id : id - 1);
      }
      addPolygon(m, ids, where);
    }
  }
  return m;
}

// PLY: ASCII or binary little endian; vertex x y z (float/double), face vertex_indices list.
TriangleMesh readPly(const std::string& path, const std::string& data) {
  std::size_t headerEnd = data.find("end_header");
  if (data.compare(0, 3, "ply") != 0 || headerEnd == std::string::npos)
    throw FileError(displayName(path) + ": not a PLY file (no 'ply' ... 'end_header')");
  std::size_t bodyStart = data.find('\n', headerEnd);
  if (bodyStart == std::string::npos) throw FileError(displayName(path) + ": PLY header not terminated");
  ++bodyStart;
  std::istringstream header(data.substr(0, headerEnd));
  std::string line, format;
  struct Prop {
    std::string name, type, countType;
    bool list = false;
  };
  struct Element {
    std::string name;
    std::size_t count = 0;
    std::vector<Prop> props;
  };
  std::vector<Element> elements;
  while (std::getline(header, line)) {
    std::istringstream ls(line);
    std::string w;
    ls >> w;
    if (w == "format") ls >> format;
    else if (w == "element") {
      Element e;
      ls >> e.name >> e.count;
      elements.push_back(e);
    } else if (w == "property") {
      if (elements.empty()) throw FileError(displayName(path) + ": PLY property before any element");
      Prop p;
      ls >> p.type;
      if (p.type == "list") {
        p.list = true;
        ls >> p.countType >> p.type;
      }
      ls >> p.name;
      elements.back().props.push_back(p);
    }
  }
  const bool ascii = format == "ascii";
  if (!ascii && format != "binary_little_endian")
    throw FileError(displayName(path) + ": PLY format '" + format +
                    "' not supported; supported: ascii, binary_little_endian");
  auto size = [&](const std::string& t) -> std::size_t {
    if (t == "char" || t == "uchar" || t == "int8" || t == "uint8") return 1;
    if (t == "short" || t == "ushort" || t == "int16" || t == "uint16") return 2;
    if (t == "int" || t == "uint" || t == "float" || t == "int32" || t == "uint32" ||
        t == "float32")
      return 4;
    if (t == "double" || t == "float64") return 8;
    throw FileError(displayName(path) + ": PLY property type '" + t + "' not supported");
  };
  std::size_t pos = bodyStart;
  std::istringstream text(ascii ? data.substr(bodyStart) : std::string());
  auto readValue = [&](const std::string& t) -> double {
    if (ascii) {
      double v;
      if (!(text >> v)) throw FileError(displayName(path) + ": PLY data ends early");
      return v;
    }
    const std::size_t n = size(t);
    if (pos + n > data.size()) throw FileError(displayName(path) + ": PLY data ends early");
    const char* p = data.data() + pos;
    pos += n;
    if (t == "float" || t == "float32") { float v; std::memcpy(&v, p, 4); return v; }
    if (t == "double" || t == "float64") { double v; std::memcpy(&v, p, 8); return v; }
    if (n == 1) return t[0] == 'u' ? double(std::uint8_t(*p)) : double(std::int8_t(*p));
    if (n == 2) {
      std::uint16_t v; std::memcpy(&v, p, 2);
      return t[0] == 'u' ? double(v) : double(std::int16_t(v));
    }
    std::uint32_t v; std::memcpy(&v, p, 4);
    return t[0] == 'u' ? double(v) : double(std::int32_t(v));
  };
  TriangleMesh m;
  for (const Element& e : elements) {
    // An element without properties takes no bytes: its count could claim anything (and
    // reading it would loop for as long as the count says).
    if (e.props.empty() && e.count > 0)
      throw FileError(displayName(path) + ": PLY element '" + e.name + "' has no properties");
    for (std::size_t i = 0; i < e.count; ++i) {
      Vec3f p{0, 0, 0};
      std::vector<long long> ids;
      for (const Prop& pr : e.props) {
        if (pr.list) {
          const std::size_t n = static_cast<std::size_t>(readValue(pr.countType));
          std::vector<long long> vals;
          for (std::size_t k = 0; k < n; ++k) vals.push_back(static_cast<long long>(readValue(pr.type)));
          if (pr.name == "vertex_indices" || pr.name == "vertex_index") ids = vals;
        } else {
          const double v = readValue(pr.type);
          if (pr.name == "x") p[0] = float(v);
          else if (pr.name == "y") p[1] = float(v);
          else if (pr.name == "z") p[2] = float(v);
        }
      }
      if (e.name == "vertex") m.positions.push_back(p);
      else if (e.name == "face") addPolygon(m, ids, displayName(path) + ": face " + std::to_string(i));
    }
  }
  return m;
}

// FreeCAD's binary mesh (layout in mesh_writers.cpp); the stored neighbours are not needed.
TriangleMesh readFreecadBms(const std::string& path, const std::string& data) {
  const std::size_t header = 8 + 256 + 8;
  std::uint32_t head[2] = {0, 0}, counts[2] = {0, 0};
  if (data.size() >= header) {
    std::memcpy(head, data.data(), 8);
    std::memcpy(counts, data.data() + 264, 8);
  }
  if (data.size() < header || head[0] != 0xA0B0C0D0u)
    throw FileError(displayName(path) + ": not a FreeCAD binary mesh (no magic number)");
  const std::size_t points = counts[0], facets = counts[1];
  if (data.size() != header + 12 * points + 24 * facets + 24)
    throw FileError(displayName(path) + ": FreeCAD binary mesh of " + std::to_string(points) + " points and " +
                    std::to_string(facets) + " facets has the wrong size");
  TriangleMesh m;
  m.positions.resize(points);
  std::memcpy(m.positions.data(), data.data() + header, 12 * points);
  m.triangles.resize(facets);
  const char* f = data.data() + header + 12 * points;
  for (std::size_t i = 0; i < facets; ++i, f += 24) {
    std::memcpy(m.triangles[i].data(), f, 12);
    for (std::uint32_t id : m.triangles[i])
      if (id >= points)
        throw FileError(displayName(path) + ": facet " + std::to_string(i) + " has point index " +
                        std::to_string(id) + " out of range (" + std::to_string(points) +
                        " points)");
  }
  return m;
}

}  // namespace

TriangleMesh readMesh(const std::string& path) {
  const MeshFormat f = formatFromPath(path);
  if (f == MeshFormat::ThreeMf) {
    TriangleMesh all;
    for (const NamedMesh& o : read3mf(path).objects) appendMesh(all, o.mesh);
    return all;
  }
  const std::string data = slurp(path);
  switch (f) {
    case MeshFormat::StlBinary:
    case MeshFormat::StlAscii: return readStl(path, data);
    case MeshFormat::Obj: return readObj(path, data);
    case MeshFormat::Ply: return readPly(path, data);
    case MeshFormat::FreecadBms: return readFreecadBms(path, data);
    case MeshFormat::ThreeMf: break;
  }
  return {};
}

}  // namespace frep
