// The only translation unit that includes lib3mf (1.8, its C interface): its headers bring
// Windows-style types and macros that must not reach the rest of libcore.
#include "io/mesh_3mf.h"

#include <Model/COM/NMR_DLLInterfaces.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <map>

#include "base/atomic_file.h"
#include "base/errors.h"
#include "base/file_names.h"
#include "base/progress.h"
#include "io/three_mf_scan.h"
#include "io/three_mf_stream.h"

namespace frep {

namespace {

using namespace NMR;
// lib3mf's C interface names each instance by a PLib3MFBase* (a void**).
using Instance = PLib3MFBase*;

constexpr const char* kUnitNames[] = {"micron", "mm", "cm", "inch", "ft", "m"};

// lib3mf's objects are reference counted; each handle this file gets is released here.
class Handle {
 public:
  Handle() = default;
  explicit Handle(Instance p) : p_(p) {}
  ~Handle() {
    if (p_) lib3mf_release(p_);
  }
  Handle(const Handle&) = delete;
  Handle& operator=(const Handle&) = delete;
  Instance* out() { return &p_; }
  Instance get() const { return p_; }

 private:
  Instance p_ = nullptr;
};

// The message of lib3mf's last error on `instance`, for a FileError.
std::string lastError(Instance instance) {
  DWORD code = 0;
  LPCSTR text = nullptr;
  if (instance && lib3mf_getlasterror(instance, &code, &text) == 0 && text && *text)
    return std::string(text) + " (lib3mf error " + std::to_string(code) + ")";
  return "lib3mf error";
}

void require(HRESULT result, Instance instance, const std::string& what) {
  if (result != 0) throw FileError(what + ": " + lastError(instance));
}

std::string objectName(Instance object) {
  ULONG needed = 0;
  if (lib3mf_object_getnameutf8(object, nullptr, 0, &needed) != 0 || needed == 0) return {};
  std::string name(needed + 1, '\0');
  if (lib3mf_object_getnameutf8(object, name.data(), ULONG(name.size()), &needed) != 0) return {};
  name.resize(std::strlen(name.c_str()));
  return name;
}

using Transform = MODELTRANSFORM;

Transform identity() {
  Transform t{};
  for (int r = 0; r < 3; ++r) t.m_fFields[r][r] = 1.0f;
  return t;
}

// a after b: the point goes through b first (3MF transforms map object to parent space).
Transform compose(const Transform& a, const Transform& b) {
  Transform t{};
  for (int r = 0; r < 3; ++r) {
    for (int c = 0; c < 3; ++c) {
      float s = 0;
      for (int k = 0; k < 3; ++k) s += a.m_fFields[r][k] * b.m_fFields[k][c];
      t.m_fFields[r][c] = s;
    }
    float s = a.m_fFields[r][3];
    for (int k = 0; k < 3; ++k) s += a.m_fFields[r][k] * b.m_fFields[k][3];
    t.m_fFields[r][3] = s;
  }
  return t;
}

bool isIdentity(const Transform& t) {
  const Transform i = identity();
  return std::memcmp(&t, &i, sizeof(t)) == 0;
}

class Flattener {
 public:
  explicit Flattener(const std::string& path) : path_(path) {}

  // Appends the triangles of `object` (mesh or components), placed by `t`.
  void add(Instance object, const Transform& t, int depth, TriangleMesh& out) {
    if (depth > kMax3mfComponentDepth)
      throw FileError(path_ + ": components nested deeper than " +
                      std::to_string(kMax3mfComponentDepth) +
                      " levels (a cycle or a hostile file)");
    BOOL isMesh = 0, isComponents = 0;
    lib3mf_object_ismeshobject(object, &isMesh);
    lib3mf_object_iscomponentsobject(object, &isComponents);
    if (isMesh) return addMesh(object, t, out);
    if (!isComponents) return;
    DWORD count = 0;
    require(lib3mf_componentsobject_getcomponentcount(object, &count), object, path_);
    for (DWORD i = 0; i < count; ++i) {
      Handle component, target;
      require(lib3mf_componentsobject_getcomponent(object, i, component.out()), object, path_);
      require(lib3mf_component_getobjectresource(component.get(), target.out()), component.get(),
              path_);
      Transform ct = identity();
      BOOL has = 0;
      lib3mf_component_hastransform(component.get(), &has);
      if (has) require(lib3mf_component_gettransform(component.get(), &ct), component.get(), path_);
      add(target.get(), compose(t, ct), depth + 1, out);
    }
  }

 private:
  void addMesh(Instance mesh, const Transform& t, TriangleMesh& out) {
    DWORD nv = 0, nt = 0;
    require(lib3mf_meshobject_getvertexcount(mesh, &nv), mesh, path_);
    require(lib3mf_meshobject_gettrianglecount(mesh, &nt), mesh, path_);
    // The whole build counts: components can instance one mesh many times.
    if (triangles_ + nt > kMax3mfTriangles)
      throw FileError(path_ + ": the build holds more than " + std::to_string(kMax3mfTriangles) +
                      " triangles; refused");
    triangles_ += nt;
    std::vector<MODELMESHVERTEX> v(nv);
    std::vector<MODELMESHTRIANGLE> tri(nt);
    DWORD got = 0;
    if (nv) require(lib3mf_meshobject_getvertices(mesh, v.data(), nv, &got), mesh, path_);
    if (nt) require(lib3mf_meshobject_gettriangleindices(mesh, tri.data(), nt, &got), mesh, path_);
    const auto base = static_cast<std::uint32_t>(out.positions.size());
    const bool moved = !isIdentity(t);
    for (const MODELMESHVERTEX& p : v) {
      Vec3f q{p.m_fPosition[0], p.m_fPosition[1], p.m_fPosition[2]};
      if (moved)
        for (int r = 0; r < 3; ++r)
          q[r] = t.m_fFields[r][0] * p.m_fPosition[0] + t.m_fFields[r][1] * p.m_fPosition[1] +
                 t.m_fFields[r][2] * p.m_fPosition[2] + t.m_fFields[r][3];
      out.positions.push_back(q);
    }
    for (const MODELMESHTRIANGLE& f : tri) {
      for (DWORD i : f.m_nIndices)
        if (i >= nv)
          throw FileError(path_ + ": a triangle of object '" + objectName(mesh) +
                          "' refers to vertex " + std::to_string(i) + " of " + std::to_string(nv));
      out.triangles.push_back(
          {base + f.m_nIndices[0], base + f.m_nIndices[1], base + f.m_nIndices[2]});
    }
  }

  const std::string& path_;
  std::size_t triangles_ = 0;  // in every build item so far
};

std::uint32_t le32(const unsigned char* p) {
  return std::uint32_t(p[0]) | std::uint32_t(p[1]) << 8 | std::uint32_t(p[2]) << 16 |
         std::uint32_t(p[3]) << 24;
}
std::uint16_t le16(const unsigned char* p) {
  return std::uint16_t(p[0] | p[1] << 8);
}
std::uint64_t le64(const unsigned char* p) {
  return std::uint64_t(le32(p)) | std::uint64_t(le32(p + 4)) << 32;
}

}  // namespace

const char* lengthUnitName(LengthUnit u) {
  return kUnitNames[static_cast<int>(u)];
}

LengthUnit parseLengthUnit(const std::string& name) {
  for (int i = 0; i < 6; ++i)
    if (name == kUnitNames[i]) return static_cast<LengthUnit>(i);
  throw ModelError("unknown unit '" + name + "'; allowed: micron, mm, cm, inch, ft, m");
}

unsigned long long zipUnpackedBytes(const std::string& path) {
  std::ifstream in(path, std::ios::binary | std::ios::ate);
  if (!in) throw FileError(path + ": cannot open");
  const auto size = static_cast<std::uint64_t>(in.tellg());
  // The end-of-central-directory record: 22 bytes plus a comment of up to 65,535.
  const std::uint64_t tail = std::min<std::uint64_t>(size, 22 + 65535);
  std::vector<unsigned char> end(tail);
  in.seekg(static_cast<std::streamoff>(size - tail));
  in.read(reinterpret_cast<char*>(end.data()), static_cast<std::streamsize>(tail));
  std::int64_t eocd = -1;
  for (std::int64_t i = std::int64_t(tail) - 22; i >= 0; --i)
    if (le32(&end[i]) == 0x06054b50u) {
      eocd = i;
      break;
    }
  const std::string notZip = path + ": not a 3MF package (no zip directory found)";
  if (eocd < 0) throw FileError(notZip);
  std::uint64_t entries = le16(&end[eocd + 10]);
  std::uint64_t dirSize = le32(&end[eocd + 12]);
  std::uint64_t dirOffset = le32(&end[eocd + 16]);
  if (entries == 0xFFFF || dirSize == 0xFFFFFFFFu || dirOffset == 0xFFFFFFFFu) {
    // Zip64: the locator just before the record points at the zip64 record.
    const std::uint64_t at = size - tail + std::uint64_t(eocd);
    if (at < 20) throw FileError(notZip);
    unsigned char loc[20], rec[56];
    in.seekg(static_cast<std::streamoff>(at - 20));
    in.read(reinterpret_cast<char*>(loc), 20);
    if (!in || le32(loc) != 0x07064b50u) throw FileError(notZip);
    in.seekg(static_cast<std::streamoff>(le64(loc + 8)));
    in.read(reinterpret_cast<char*>(rec), 56);
    if (!in || le32(rec) != 0x06064b50u) throw FileError(notZip);
    entries = le64(rec + 32);
    dirSize = le64(rec + 40);
    dirOffset = le64(rec + 48);
  }
  if (dirOffset > size || dirSize > size - dirOffset || entries > dirSize / 46)
    throw FileError(path + ": the zip directory is damaged (it lies beyond the file)");
  std::vector<unsigned char> dir(dirSize);
  in.seekg(static_cast<std::streamoff>(dirOffset));
  in.read(reinterpret_cast<char*>(dir.data()), static_cast<std::streamsize>(dirSize));
  if (!in) throw FileError(path + ": the zip directory cannot be read");
  unsigned long long total = 0;
  std::size_t p = 0;
  for (std::uint64_t e = 0; e < entries; ++e) {
    if (p + 46 > dir.size() || le32(&dir[p]) != 0x02014b50u)
      throw FileError(path + ": the zip directory is damaged");
    std::uint64_t unpacked = le32(&dir[p + 24]);
    const std::size_t nameLen = le16(&dir[p + 28]), extraLen = le16(&dir[p + 30]),
                      commentLen = le16(&dir[p + 32]);
    const std::size_t extra = p + 46 + nameLen;
    if (extra + extraLen + commentLen > dir.size())
      throw FileError(path + ": the zip directory is damaged");
    if (unpacked == 0xFFFFFFFFu) {
      // The zip64 extra field (id 1) holds the real size first.
      bool found = false;
      for (std::size_t x = extra; x + 4 <= extra + extraLen;) {
        const std::size_t id = le16(&dir[x]), len = le16(&dir[x + 2]);
        if (id == 1 && len >= 8 && x + 12 <= extra + extraLen) {
          unpacked = le64(&dir[x + 4]);
          found = true;
          break;
        }
        x += 4 + len;
      }
      if (!found) throw FileError(path + ": the zip directory is damaged (zip64 size missing)");
    }
    total += unpacked;
    if (total > (1ull << 62)) break;
    p = extra + extraLen + commentLen;
  }
  return total;
}

namespace {

// Everything a read model holds: the build items, flattened; the unit; the metadata.
ThreeMfContents contentsOf(Instance model, const std::string& path) {
  ThreeMfContents c;
  DWORD unit = 1;
  lib3mf_model_getunit(model, &unit);
  c.unit = unit <= 5 ? static_cast<LengthUnit>(unit) : LengthUnit::Millimeter;
  DWORD metadata = 0;
  lib3mf_model_getmetadatacount(model, &metadata);
  for (DWORD i = 0; i < metadata; ++i) {
    auto text = [&](auto get) {
      ULONG needed = 0;
      if (get(model, i, nullptr, 0, &needed) != 0) return std::string();
      std::string s(needed + 1, '\0');
      if (get(model, i, s.data(), ULONG(s.size()), &needed) != 0) return std::string();
      s.resize(std::strlen(s.c_str()));
      return s;
    };
    c.metadata.emplace_back(text(lib3mf_model_getmetadatakeyutf8),
                            text(lib3mf_model_getmetadatavalueutf8));
  }
  Handle items;
  require(lib3mf_model_getbuilditems(model, items.out()), model, path);
  Flattener flatten(path);
  BOOL more = 0;
  while (lib3mf_builditemiterator_movenext(items.get(), &more) == 0 && more) {
    Handle item, object;
    require(lib3mf_builditemiterator_getcurrent(items.get(), item.out()), items.get(), path);
    require(lib3mf_builditem_getobjectresource(item.get(), object.out()), item.get(), path);
    Transform t = identity();
    BOOL has = 0;
    lib3mf_builditem_hasobjecttransform(item.get(), &has);
    if (has) require(lib3mf_builditem_getobjecttransform(item.get(), &t), item.get(), path);
    NamedMesh o;
    o.name = objectName(object.get());
    if (o.name.empty()) o.name = "object " + std::to_string(c.objects.size() + 1);
    flatten.add(object.get(), t, 0, o.mesh);
    c.objects.push_back(std::move(o));
  }
  if (c.objects.empty()) throw FileError(path + ": the 3MF build has no objects");
  return c;
}

}  // namespace

void validate3mfObjects(const std::vector<NamedMesh>& objects) {
  for (const NamedMesh& o : objects) {
    const std::string what = "3MF object '" + o.name + "'";
    if (o.mesh.triangles.empty()) throw FileError(what + " has no triangles");
    if (o.mesh.positions.size() > 0xFFFFFFF0u || o.mesh.triangles.size() > 0xFFFFFFF0u)
      throw FileError(what + " has too many vertices or triangles for 3MF");
    for (const Triangle& t : o.mesh.triangles)
      for (std::uint32_t v : t)
        if (v >= o.mesh.positions.size())
          throw FileError(what + ": a triangle refers to vertex " + std::to_string(v) + " of " +
                          std::to_string(o.mesh.positions.size()));
    // lib3mf's own judgement of the rule, on a model that is never written
    Handle model, mesh;
    require(lib3mf_createmodel(model.out()), nullptr, "3MF: cannot start a model");
    require(lib3mf_model_addmeshobject(model.get(), mesh.out()), model.get(), what);
    static_assert(sizeof(MODELMESHVERTEX) == sizeof(Vec3f), "3MF vertices are three floats");
    static_assert(sizeof(MODELMESHTRIANGLE) == sizeof(Triangle), "3MF triangles are three indices");
    require(
        lib3mf_meshobject_setgeometry(
            mesh.get(),
            reinterpret_cast<MODELMESHVERTEX*>(const_cast<Vec3f*>(o.mesh.positions.data())),
            DWORD(o.mesh.positions.size()),
            reinterpret_cast<MODELMESHTRIANGLE*>(const_cast<Triangle*>(o.mesh.triangles.data())),
            DWORD(o.mesh.triangles.size())),
        mesh.get(), what);
    BOOL ok = 0;
    require(lib3mf_meshobject_ismanifoldandoriented(mesh.get(), &ok), mesh.get(), what);
    if (!ok)
      throw FileError(what +
                      " is not manifold and consistently oriented, which the 3MF core "
                      "specification requires (frepcad repair can mend it)");
  }
}

std::unique_ptr<AtomicFile> write3mfUncommitted(const std::vector<NamedMesh>& objects,
                                                const std::string& path,
                                                const ThreeMfOptions& options,
                                                const WriteProgress& progress) {
  if (objects.empty()) throw FileError("3MF: no objects to write");
  if (options.validate) validate3mfObjects(objects);
  std::uint64_t vertices = 0, triangles = 0;
  for (const NamedMesh& o : objects) {
    vertices += o.mesh.positions.size();
    triangles += o.mesh.triangles.size();
  }
  ThreeMfStreamWriter writer(path, options, expectedXmlBytes(vertices, triangles));
  const double total = static_cast<double>(vertices + triangles) + 1.0;
  const Progress writing = Progress(progress).sub(0.0, 0.95);  // (the commit the rest)
  std::uint64_t done = 0;
  auto written = [&](std::size_t n) {
    done += n;
    writing.step(double(done) / total);
  };
  for (const NamedMesh& o : objects) writer.addObject(o.name, o.mesh, written);
  return writer.finish();
}

void write3mf(const std::vector<NamedMesh>& objects, const std::string& path,
              const ThreeMfOptions& options, const WriteProgress& progress) {
  const std::unique_ptr<AtomicFile> file = write3mfUncommitted(objects, path, options, progress);
  Progress(progress).step(1.0);
  file->commit();
}

ThreeMfBeams read3mfBeams(const std::string& file) {
  requireRegularFile(file, "a 3MF file");
  const std::string path = displayName(file);
  if (zipUnpackedBytes(file) > kMax3mfUnpackedBytes)
    throw FileError(path + ": the package unpacks to more than " +
                    std::to_string(kMax3mfUnpackedBytes >> 20) + " MiB; refused before reading");
  Handle model, reader, objects;
  require(lib3mf_createmodel(model.out()), nullptr, path + ": cannot start a 3MF model");
  require(lib3mf_model_queryreader(model.get(), "3mf", reader.out()), model.get(), path);
  if (lib3mf_reader_readfromfileutf8(reader.get(), file.c_str()) != 0)
    throw FileError(path + ": not a readable 3MF file: " + lastError(reader.get()));
  require(lib3mf_model_getmeshobjects(model.get(), objects.out()), model.get(), path);
  ThreeMfBeams b;
  BOOL more = 0;
  while (lib3mf_resourceiterator_movenext(objects.get(), &more) == 0 && more) {
    Handle mesh;
    require(lib3mf_resourceiterator_getcurrent(objects.get(), mesh.out()), objects.get(), path);
    DWORD count = 0;
    require(lib3mf_meshobject_getbeamcount(mesh.get(), &count), mesh.get(), path);
    b.beams += count;
    if (count) {
      DWORD nv = 0, got = 0;
      require(lib3mf_meshobject_getvertexcount(mesh.get(), &nv), mesh.get(), path);
      std::vector<MODELMESHVERTEX> v(nv);
      if (nv) require(lib3mf_meshobject_getvertices(mesh.get(), v.data(), nv, &got), mesh.get(), path);
      std::vector<MODELMESHBEAM> beams(count);
      require(lib3mf_meshobject_getbeamindices(mesh.get(), beams.data(), count, &got), mesh.get(),
              path);
      auto at = [&](DWORD i) {
        if (i >= nv) throw FileError(path + ": a beam names vertex " + std::to_string(i) +
                                     " of " + std::to_string(nv));
        return Vec3f{v[i].m_fPosition[0], v[i].m_fPosition[1], v[i].m_fPosition[2]};
      };
      for (const MODELMESHBEAM& beam : beams) {
        b.ends.push_back({at(beam.m_nIndices[0]), at(beam.m_nIndices[1])});
        b.radii.push_back({beam.m_dRadius[0], beam.m_dRadius[1]});
      }
    }
    eModelBeamLatticeClipMode mode = MODELBEAMLATTICECLIPMODE_NONE;
    DWORD id = 0;
    if (count && lib3mf_meshobject_getbeamlattice_clipping(mesh.get(), &mode, &id) == 0 &&
        mode != MODELBEAMLATTICECLIPMODE_NONE)
      ++b.clipped;
  }
  return b;
}

ThreeMfContents read3mf(const std::string& file) {
  requireRegularFile(file, "a 3MF file");
  const std::string path = displayName(file);
  const unsigned long long unpacked = zipUnpackedBytes(file);
  if (unpacked > kMax3mfUnpackedBytes)
    throw FileError(path + ": the package unpacks to " + std::to_string(unpacked >> 20) +
                    " MiB, over the " + std::to_string(kMax3mfUnpackedBytes >> 20) +
                    " MiB a 3MF may take here; refused before reading (a zip bomb?)");
  const ThreeMfExpansion expansion = scan3mfExpansion(file, path, kMax3mfComponentDepth);
  if (expansion.triangles > double(kMax3mfTriangles))
    throw FileError(path + ": the build holds " +
                    std::to_string(std::llround(expansion.triangles)) +
                    " triangles once its components are expanded, more than " +
                    std::to_string(kMax3mfTriangles) + "; refused before reading");
  if (expansion.placements > double(kMax3mfPlacements))
    throw FileError(path + ": the build places objects " +
                    std::to_string(std::llround(expansion.placements)) +
                    " times once its components are expanded, more than " +
                    std::to_string(kMax3mfPlacements) + "; refused before reading");
  Handle model, reader;
  require(lib3mf_createmodel(model.out()), nullptr, path + ": cannot start a 3MF model");
  require(lib3mf_model_queryreader(model.get(), "3mf", reader.out()), model.get(), path);
  if (lib3mf_reader_readfromfileutf8(reader.get(), file.c_str()) != 0)
    throw FileError(path + ": not a readable 3MF file: " + lastError(reader.get()));
  return contentsOf(model.get(), path);
}

}  // namespace frep
