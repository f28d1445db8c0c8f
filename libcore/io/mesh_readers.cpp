#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <sstream>

#include "base/errors.h"
#include "base/file_names.h"
#include "io/mesh_3mf.h"
#include "io/mesh_io.h"

namespace frep {

namespace {

// Triangles, lines or elements read between two looks at the caller's cancel (a few
// milliseconds of reading).
constexpr std::size_t kItemsBetweenPolls = 1 << 18;

// The whole file, read in blocks with the caller's cancel looked at between them (an 800 MB
// STL takes seconds).
std::string slurp(const std::string& path, const Progress& cancel) {
  requireRegularFile(path, "a mesh file");  // a FIFO would block, a folder reads as empty
  std::ifstream in(path, std::ios::binary | std::ios::ate);
  if (!in) throw FileError(displayName(path) + ": cannot open the file");
  const std::streamoff size = in.tellg();
  in.seekg(0);
  std::string data(static_cast<std::size_t>(std::max<std::streamoff>(size, 0)), '\0');
  constexpr std::size_t kBlock = std::size_t(1) << 24;
  for (std::size_t at = 0; at < data.size(); at += kBlock) {
    cancel.step(double(at) / double(data.size()));
    const std::size_t n = std::min(kBlock, data.size() - at);
    if (!in.read(&data[at], static_cast<std::streamsize>(n)))
      throw FileError(displayName(path) + ": read error");
  }
  return data;
}

// Whitespace-separated words of a line, up to a '#' comment when `comments`.
std::vector<std::string> wordsOf(const std::string& line, bool comments) {
  std::istringstream ls(comments ? line.substr(0, line.find('#')) : line);
  std::vector<std::string> words;
  for (std::string w; ls >> w;) words.push_back(w);
  return words;
}

// A word that is one number and nothing else: "1abc", "one" and "" are refused, and so are
// infinities and NaN (a vertex there has no place).
double strictReal(const std::string& word, const std::string& where) {
  const char* begin = word.c_str();
  char* end = nullptr;
  errno = 0;
  const double v = std::strtod(begin, &end);
  if (end == begin || *end != '\0' || !std::isfinite(v) || errno == ERANGE)
    throw FileError(where + ": '" + word.substr(0, 40) + "' is not a finite number");
  return v;
}

// A word that is one whole number: "1.9" and "1abc" are refused rather than read as 1.
long long strictInteger(const std::string& word, const std::string& where) {
  const char* begin = word.c_str();
  char* end = nullptr;
  errno = 0;
  const long long v = std::strtoll(begin, &end, 10);
  if (end == begin || *end != '\0' || errno == ERANGE)
    throw FileError(where + ": '" + word.substr(0, 40) + "' is not a whole number");
  return v;
}

Vec3f strictPoint(const std::vector<std::string>& words, std::size_t first,
                  const std::string& where) {
  Vec3f p;
  for (int c = 0; c < 3; ++c) {
    const double v = strictReal(words[first + c], where);
    if (std::fabs(v) > 3.0e38)
      throw FileError(where + ": coordinate " + words[first + c].substr(0, 40) +
                      " is beyond the range of a 32-bit float");
    p[c] = static_cast<float>(v);
  }
  return p;
}

// The most corners a polygon may have: it becomes a fan of slivers from its first corner,
// whose pairs the check must test (a million-corner face is half a trillion pairs); real
// polygons, a cylinder's cap included, have a few hundred to a few thousand.
constexpr std::size_t kMaxPolygonCorners = 10000;

// Adds a polygon as a fan of triangles after checking its indices.
void addPolygon(TriangleMesh& m, const std::vector<long long>& ids, const std::string& where) {
  if (ids.size() < 3) throw FileError(where + ": a face needs at least 3 vertices");
  if (ids.size() > kMaxPolygonCorners)
    throw FileError(where + ": a face of " + std::to_string(ids.size()) + " corners; at most " +
                    std::to_string(kMaxPolygonCorners) +
                    " are read (a polygon becomes a fan of slivers from its first corner)");
  for (long long id : ids)
    if (id < 0 || static_cast<std::size_t>(id) >= m.positions.size())
      throw FileError(where + ": vertex index " + std::to_string(id) + " out of range (" +
                      std::to_string(m.positions.size()) + " vertices)");
  for (std::size_t i = 1; i + 1 < ids.size(); ++i)
    m.triangles.push_back({static_cast<std::uint32_t>(ids[0]), static_cast<std::uint32_t>(ids[i]),
                           static_cast<std::uint32_t>(ids[i + 1])});
}

TriangleMesh readStl(const std::string& path, const std::string& data, const Progress& cancel) {
  TriangleMesh m;
  if (data.size() >= 84) {
    std::uint32_t n = 0;
    std::memcpy(&n, data.data() + 80, 4);
    if (data.size() == 84 + 50ull * n) {
      m.positions.reserve(3ull * n);
      m.triangles.reserve(n);  // (growing it copied 400 MB at once at 33 million faces)
      for (std::uint32_t i = 0; i < n; ++i) {
        if (i % kItemsBetweenPolls == 0) cancel.step(double(i) / n);
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
    throw FileError(displayName(path) +
                    ": not an STL file (binary size does not match its triangle count, "
                    "and it does not start with 'solid')");
  // ASCII STL, read strictly: a garbage file is bad input (exit 2), not an empty mesh that
  // the check would call "not printable".
  std::istringstream in(data);
  std::string line;
  std::size_t lineNo = 0, inLoop = 0;
  bool ended = false, loop = false;
  while (std::getline(in, line)) {
    if (++lineNo % kItemsBetweenPolls == 0) cancel.step(0.0);
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
  if (!ended)
    throw FileError(displayName(path) + ": ASCII STL ends without 'endsolid' (a truncated file?)");
  return m;
}

// OBJ: 'v' and 'f' lines (texture and normal references after '/' are ignored; negative
// indices count back from the last vertex); other statements (vt, vn, g, o, usemtl, ...) are
// not geometry and are skipped.
TriangleMesh readObj(const std::string& path, const std::string& data, const Progress& cancel) {
  TriangleMesh m;
  std::istringstream in(data);
  std::string line;
  std::size_t lineNo = 0;
  while (std::getline(in, line)) {
    if (++lineNo % kItemsBetweenPolls == 0) cancel.step(0.0);
    const std::vector<std::string> words = wordsOf(line, true);
    if (words.empty()) continue;
    const std::string where = displayName(path) + ":" + std::to_string(lineNo);
    if (words[0] == "v") {
      // x y z, then an optional w or an r g b colour
      if (words.size() < 4) throw FileError(where + ": 'v' needs three numbers");
      m.positions.push_back(strictPoint(words, 1, where));
    } else if (words[0] == "f") {
      std::vector<long long> ids;
      for (std::size_t i = 1; i < words.size(); ++i) {
        const long long id = strictInteger(words[i].substr(0, words[i].find('/')), where);
        if (id == 0)
          throw FileError(where +
                          ": face index 0; OBJ counts vertices from 1 (and back from "
                          "the last with -1)");
        ids.push_back(id < 0 ? static_cast<long long>(m.positions.size()) + id : id - 1);
      }
      addPolygon(m, ids, where);
    }
  }
  return m;
}

// OFF (Object File Format): "OFF", the vertex, face and edge counts, one vertex a line (x y
// z, then optional colour or normal values), one face a line (n, n indices counted from 0,
// then an optional colour). The counts are checked against the file's size before anything
// is reserved: a header may claim what the file does not hold.
TriangleMesh readOff(const std::string& path, const std::string& data, const Progress& cancel) {
  std::istringstream in(data);
  std::string line;
  std::size_t lineNo = 0;
  std::vector<std::string> words;
  auto next = [&]() {
    while (std::getline(in, line)) {
      if (++lineNo % kItemsBetweenPolls == 0) cancel.step(0.0);
      words = wordsOf(line, true);
      if (!words.empty()) return true;
    }
    return false;
  };
  auto where = [&]() { return displayName(path) + ":" + std::to_string(lineNo); };
  if (!next()) throw FileError(displayName(path) + ": empty file; an OFF file starts with 'OFF'");
  const std::string keyword = words[0];
  const bool offKeyword = keyword.size() >= 3 &&
                          keyword.compare(keyword.size() - 3, 3, "OFF") == 0 &&
                          keyword.find_first_not_of("STCNOF") == std::string::npos;
  if (!offKeyword)
    throw FileError(where() + ": not an OFF file (it starts with '" + keyword.substr(0, 40) +
                    "'; supported headers: OFF, COFF, NOFF, CNOFF, STOFF)");
  if (words.size() > 1 && words[1] == "BINARY")
    throw FileError(where() + ": binary OFF is not supported; write it as text OFF");
  words.erase(words.begin());  // the counts may follow the keyword on its line
  if (words.empty() && !next()) throw FileError(where() + ": OFF header without counts");
  if (words.size() < 2) throw FileError(where() + ": OFF counts need vertices and faces");
  const long long nv = strictInteger(words[0], where()), nf = strictInteger(words[1], where());
  // every vertex takes at least 6 bytes ("0 0 0\n"), every face 8 ("3 0 1 2\n")
  if (nv < 0 || nf < 0 || static_cast<unsigned long long>(nv) > data.size() / 6 ||
      static_cast<unsigned long long>(nf) > data.size() / 8)
    throw FileError(where() + ": OFF header claims " + std::to_string(nv) + " vertices and " +
                    std::to_string(nf) + " faces, more than " + std::to_string(data.size()) +
                    " bytes can hold");
  TriangleMesh m;
  m.positions.reserve(static_cast<std::size_t>(nv));
  for (long long i = 0; i < nv; ++i) {
    if (!next())
      throw FileError(displayName(path) + ": OFF ends after " + std::to_string(i) + " of " +
                      std::to_string(nv) + " vertices");
    const std::string at = where();
    if (words.size() < 3) throw FileError(at + ": an OFF vertex needs three numbers");
    m.positions.push_back(strictPoint(words, 0, at));
  }
  for (long long i = 0; i < nf; ++i) {
    if (!next())
      throw FileError(displayName(path) + ": OFF ends after " + std::to_string(i) + " of " +
                      std::to_string(nf) + " faces");
    const std::string at = where();  // (once a face, not once an index)
    const long long n = strictInteger(words[0], at);
    if (n < 0 || static_cast<unsigned long long>(n) + 1 > words.size())
      throw FileError(at + ": OFF face says " + std::to_string(n) + " vertices but lists " +
                      std::to_string(words.size() - 1) + " numbers");
    std::vector<long long> ids;
    for (long long k = 1; k <= n; ++k) ids.push_back(strictInteger(words[k], at));
    addPolygon(m, ids, at);
  }
  if (next())
    throw FileError(where() + ": text after the last of the " + std::to_string(nf) +
                    " faces the OFF header counts");
  return m;
}

// PLY: ASCII or binary little endian; vertex x y z (float/double), face vertex_indices list.
TriangleMesh readPly(const std::string& path, const std::string& data, const Progress& cancel) {
  std::size_t headerEnd = data.find("end_header");
  if (data.compare(0, 3, "ply") != 0 || headerEnd == std::string::npos)
    throw FileError(displayName(path) + ": not a PLY file (no 'ply' ... 'end_header')");
  std::size_t bodyStart = data.find('\n', headerEnd);
  if (bodyStart == std::string::npos)
    throw FileError(displayName(path) + ": PLY header not terminated");
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
  auto size = [&](const std::string& t) -> std::size_t {
    if (t == "char" || t == "uchar" || t == "int8" || t == "uint8") return 1;
    if (t == "short" || t == "ushort" || t == "int16" || t == "uint16") return 2;
    if (t == "int" || t == "uint" || t == "float" || t == "int32" || t == "uint32" ||
        t == "float32")
      return 4;
    if (t == "double" || t == "float64") return 8;
    throw FileError(displayName(path) + ": PLY property type '" + t.substr(0, 40) +
                    "' is not one of char, uchar, short, ushort, int, uint, float, double "
                    "(or int8 ... float64)");
  };
  std::size_t headerLine = 0;
  while (std::getline(header, line)) {
    ++headerLine;
    const std::vector<std::string> w = wordsOf(line, false);
    if (w.empty()) continue;
    const std::string where = displayName(path) + ":" + std::to_string(headerLine);
    if (w[0] == "format") {
      if (w.size() < 2) throw FileError(where + ": PLY 'format' needs a format name");
      format = w[1];
    } else if (w[0] == "element") {
      if (w.size() != 3) throw FileError(where + ": PLY 'element' needs a name and a count");
      const long long count = strictInteger(w[2], where);
      if (count < 0) throw FileError(where + ": PLY element count " + w[2] + " is negative");
      Element e;
      e.name = w[1];
      e.count = static_cast<std::size_t>(count);
      elements.push_back(e);
    } else if (w[0] == "property") {
      if (elements.empty()) throw FileError(where + ": PLY property before any element");
      Prop p;
      if (w.size() == 5 && w[1] == "list") {
        p.list = true;
        p.countType = w[2];
        p.type = w[3];
        p.name = w[4];
        size(p.countType);
      } else if (w.size() == 3) {
        p.type = w[1];
        p.name = w[2];
      } else {
        throw FileError(where +
                        ": PLY 'property' needs a type and a name (or 'list', two "
                        "types and a name)");
      }
      size(p.type);
      elements.back().props.push_back(p);
    }
  }
  const bool ascii = format == "ascii";
  if (!ascii && format != "binary_little_endian")
    throw FileError(displayName(path) + ": PLY format '" + format +
                    "' not supported; supported: ascii, binary_little_endian");
  std::size_t pos = bodyStart;
  std::istringstream text(ascii ? data.substr(bodyStart) : std::string());
  const std::string dataWhere = displayName(path) + ": PLY data";  // (once, not per value)
  auto readValue = [&](const std::string& t) -> double {
    if (ascii) {
      std::string word;
      if (!(text >> word)) throw FileError(displayName(path) + ": PLY data ends early");
      const bool real = t == "float" || t == "float32" || t == "double" || t == "float64";
      return real ? strictReal(word, dataWhere) : double(strictInteger(word, dataWhere));
    }
    const std::size_t n = size(t);
    if (pos + n > data.size()) throw FileError(displayName(path) + ": PLY data ends early");
    const char* p = data.data() + pos;
    pos += n;
    if (t == "float" || t == "float32") {
      float v;
      std::memcpy(&v, p, 4);
      return v;
    }
    if (t == "double" || t == "float64") {
      double v;
      std::memcpy(&v, p, 8);
      return v;
    }
    if (n == 1) return t[0] == 'u' ? double(std::uint8_t(*p)) : double(std::int8_t(*p));
    if (n == 2) {
      std::uint16_t v;
      std::memcpy(&v, p, 2);
      return t[0] == 'u' ? double(v) : double(std::int16_t(v));
    }
    std::uint32_t v;
    std::memcpy(&v, p, 4);
    return t[0] == 'u' ? double(v) : double(std::int32_t(v));
  };
  TriangleMesh m;
  for (const Element& e : elements) {
    // An element without properties takes no bytes: its count could claim anything (and
    // reading it would loop for as long as the count says).
    if (e.props.empty() && e.count > 0)
      throw FileError(displayName(path) + ": PLY element '" + e.name + "' has no properties");
    for (std::size_t i = 0; i < e.count; ++i) {
      if (i % kItemsBetweenPolls == 0) cancel.step(0.0);
      Vec3f p{0, 0, 0};
      std::vector<long long> ids;
      for (const Prop& pr : e.props) {
        if (pr.list) {
          const double count = readValue(pr.countType);
          if (count < 0)
            throw FileError(displayName(path) + ": PLY " + e.name + " " + std::to_string(i) +
                            " has a list of " + std::to_string(count) + " values");
          const std::size_t n = static_cast<std::size_t>(count);
          std::vector<long long> vals;
          for (std::size_t k = 0; k < n; ++k)
            vals.push_back(static_cast<long long>(readValue(pr.type)));
          if (pr.name == "vertex_indices" || pr.name == "vertex_index") ids = vals;
        } else {
          const double v = readValue(pr.type);
          if (pr.name == "x")
            p[0] = float(v);
          else if (pr.name == "y")
            p[1] = float(v);
          else if (pr.name == "z")
            p[2] = float(v);
        }
      }
      if (e.name == "vertex")
        m.positions.push_back(p);
      else if (e.name == "face")
        addPolygon(m, ids, displayName(path) + ": face " + std::to_string(i));
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
    throw FileError(displayName(path) + ": FreeCAD binary mesh of " + std::to_string(points) +
                    " points and " + std::to_string(facets) + " facets has the wrong size");
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

namespace {

TriangleMesh readByExtension(const std::string& path, const Progress& cancel) {
  // OFF is read, never written: it is not a MeshFormat
  if (fileExtension(path) == "off") return readOff(path, slurp(path, cancel), cancel);
  const MeshFormat f = formatFromPath(path, "read: .stl, .obj, .ply, .off, .bms, .3mf");
  if (f == MeshFormat::ThreeMf) {
    TriangleMesh all;
    for (const NamedMesh& o : read3mf(path).objects) appendMesh(all, o.mesh);
    return all;
  }
  const std::string data = slurp(path, cancel);
  switch (f) {
    case MeshFormat::StlBinary:
    case MeshFormat::StlAscii:
      return readStl(path, data, cancel);
    case MeshFormat::Obj:
      return readObj(path, data, cancel);
    case MeshFormat::Ply:
      return readPly(path, data, cancel);
    case MeshFormat::FreecadBms:
      return readFreecadBms(path, data);
    case MeshFormat::ThreeMf:
      break;
  }
  return {};
}

}  // namespace

TriangleMesh readMesh(const std::string& path, const Progress& cancel) {
  TriangleMesh m = readByExtension(path, cancel);
  // Points alone are not a surface: a point cloud or an emptied file is bad input, not a
  // mesh that the check would call "not printable".
  if (m.triangles.empty())
    throw FileError(displayName(path) + ": no faces (" + std::to_string(m.positions.size()) +
                    " vertices); a mesh file needs triangles or polygons");
  return m;
}

}  // namespace frep
