// .vdb files through openvdb::io::File (the header and the grids' metadata), io::Stream (the
// grids, from a stream that throws at its end) and io::File again to write (into a temporary
// file made atomic), with every OpenVDB error turned into a FileError that names the file.
#include <openvdb/io/File.h>
#include <openvdb/io/Stream.h>

#include <cstdint>
#include <fstream>
#include <mutex>
#include <sstream>

#include "base/atomic_file.h"
#include "base/errors.h"
#include "base/file_names.h"
#include "volume/openvdb_grids.h"

namespace frep {

void initializeOpenVdb() {
  static std::once_flag once;
  std::call_once(once, [] { openvdb::initialize(); });
}

GridSet::GridSet() : impl(std::make_shared<Impl>()) {}

GridSet gridSetOf(openvdb::GridPtrVec grids) {
  GridSet s;
  s.impl->grids = std::move(grids);
  return s;
}

std::size_t GridSet::size() const {
  return impl->grids.size();
}

namespace {

std::string className(openvdb::GridClass c) {
  switch (c) {
    case openvdb::GRID_LEVEL_SET:
      return "level set";
    case openvdb::GRID_FOG_VOLUME:
      return "fog volume";
    case openvdb::GRID_STAGGERED:
      return "staggered";
    default:
      return "unknown";
  }
}

bool isScalar(const openvdb::GridBase& g) {
  return g.isType<openvdb::FloatGrid>() || g.isType<openvdb::DoubleGrid>();
}

std::string withThousands(std::uint64_t n) {
  std::string s = std::to_string(n);
  for (int i = static_cast<int>(s.size()) - 3; i > 0; i -= 3)
    s.insert(static_cast<std::size_t>(i), ",");
  return s;
}

}  // namespace

GridInfo GridSet::info(std::size_t i) const {
  const openvdb::GridBase& g = *impl->grids.at(i);
  GridInfo out;
  out.name = g.getName();
  out.valueType = g.valueType();
  out.gridClass = className(g.getGridClass());
  const openvdb::Vec3d v = g.voxelSize();
  out.voxelSize = {v[0], v[1], v[2]};
  out.activeVoxels = g.activeVoxelCount();
  const openvdb::CoordBBox ib = g.evalActiveVoxelBoundingBox();
  if (ib.empty()) {
    out.worldBox = Box3{{1, 1, 1}, {0, 0, 0}};
  } else {
    // The box of the active voxels' centres' cells, through the grid's transform.
    const openvdb::BBoxd wb = g.transform().indexToWorld(
        openvdb::BBoxd(ib.min().asVec3d() - 0.5, ib.max().asVec3d() + 0.5));
    out.worldBox =
        Box3{{wb.min()[0], wb.min()[1], wb.min()[2]}, {wb.max()[0], wb.max()[1], wb.max()[2]}};
  }
  for (auto it = g.beginMeta(); it != g.endMeta(); ++it)
    out.metadata[it->first] = it->second ? it->second->str() : "";
  return out;
}

std::size_t GridSet::scalarGrid(const std::string& name, const std::string& where) const {
  std::string listing;
  for (std::size_t i = 0; i < size(); ++i) {
    const openvdb::GridBase& g = *impl->grids[i];
    if ((name.empty() || g.getName() == name) && isScalar(g)) return i;
    if (!name.empty() && g.getName() == name)
      throw ModelError(where + ": grid '" + name + "' holds " + g.valueType() +
                       " values; a solid needs a float or double grid");
    listing += (listing.empty() ? "" : ", ") + ("'" + g.getName() + "' (" + g.valueType() + ")");
  }
  if (listing.empty()) listing = "none";
  if (name.empty())
    throw ModelError(where + ": no float or double grid; the file's grids: " + listing);
  throw ModelError(where + ": no grid named '" + name + "'; the file's grids: " + listing);
}

std::string describeGrid(const GridInfo& g) {
  std::ostringstream s;
  s << "grid '" << g.name << "' (" << g.valueType << ", " << g.gridClass << ", "
    << withThousands(g.activeVoxels) << " active voxels, voxel " << g.voxelSize[0];
  if (g.voxelSize[1] != g.voxelSize[0] || g.voxelSize[2] != g.voxelSize[0])
    s << " x " << g.voxelSize[1] << " x " << g.voxelSize[2];
  s << ")";
  return s.str();
}

namespace {

// The sizes an OpenVDB file declares before its grids, each checked against the bytes left in
// the file before OpenVDB allocates by it: its metadata (a count, then per entry a name and a
// type name of a declared length and a value of a declared size), the grid count, and each
// grid's descriptor (its name, type and parent names and three file offsets) and metadata.
// OpenVDB sizes a string by the length the file declares and fills it before reading: a
// 162-byte file declaring names of 2 GB took 20 GB and a minute before it failed. Files
// without grid offsets (written to a stream) and formats before 222 get the metadata check
// only where their layout is the same. The fixed header comes first: a file cut short there is
// refused with what is wrong, where OpenVDB would log a warning and report a file of no grids.
class VdbLayoutCheck {
 public:
  VdbLayoutCheck(const std::string& path, const std::string& name)
      : name_(name), in_(path, std::ios::binary) {
    in_.seekg(0, std::ios::end);
    size_ = static_cast<std::uint64_t>(std::max<std::streamoff>(0, in_.tellg()));
  }

  void run() {
    const std::uint32_t version = header();
    char hasOffsets = 0;
    bytes(&hasOffsets, 1);
    if (version < openvdb::OPENVDB_FILE_VERSION_NODE_MASK_COMPRESSION) return;
    seek(kFixedHeader);  // (past the UUID)
    metaMap("the file's metadata");
    if (!hasOffsets) return;
    const std::uint32_t grids = u32();
    // (a descriptor takes at least three empty names and three offsets)
    if (grids > left() / 36) fail("a grid count of " + std::to_string(grids));
    for (std::uint32_t g = 0; g < grids; ++g) {
      for (int k = 0; k < 3; ++k) string("a grid's name");
      const std::uint64_t gridPos = u64(), blockPos = u64(), endPos = u64();
      if (gridPos > size_ || blockPos > size_ || endPos > size_ || endPos < at())
        fail("a grid's offsets");
      const std::uint64_t next = endPos;
      seek(gridPos + 4);  // (past the grid's compression flags)
      metaMap("a grid's metadata");
      seek(next);
      (void)blockPos;
    }
  }

 private:
  // The magic number (int64), the file format version (uint32), the library's major and minor
  // versions (uint32 each), a grid-offsets flag (1 byte) and a 36-character UUID.
  static constexpr std::uint64_t kFixedHeader = 8 + 4 + 4 + 4 + 1 + 36;

  // Checks the magic number and the format version; returns the version, the stream past
  // the library's versions (at the offsets flag).
  std::uint32_t header() {
    constexpr std::int64_t kMagic = 0x56444220;  // " BDV"
    std::int64_t magic = 0;
    seek(0);
    if (size_ >= 8) bytes(&magic, 8);
    if (size_ < 8 || magic != kMagic)
      throw FileError(name_ + ": not an OpenVDB file (no OpenVDB magic number at its start)");
    if (size_ < kFixedHeader)
      throw FileError(name_ + ": the OpenVDB file ends inside its header (" +
                      std::to_string(size_) + " of at least " + std::to_string(kFixedHeader) +
                      " bytes): a truncated file");
    const std::uint32_t version = u32();
    if (version < openvdb::OPENVDB_FILE_VERSION_ROOTNODE_MAP ||
        version > openvdb::OPENVDB_FILE_VERSION)
      throw FileError(name_ + ": OpenVDB file format version " + std::to_string(version) +
                      " is not one this build reads (" +
                      std::to_string(openvdb::OPENVDB_FILE_VERSION_ROOTNODE_MAP) + " to " +
                      std::to_string(openvdb::OPENVDB_FILE_VERSION) + ")");
    skip(8, "the library's version");
    return version;
  }

  [[noreturn]] void fail(const std::string& what) const {
    throw FileError(name_ + ": the OpenVDB file is damaged: " + what + " at byte " +
                    std::to_string(at_) + " does not fit in its " + std::to_string(size_) +
                    " bytes");
  }
  std::uint64_t at() const { return at_; }
  std::uint64_t left() const { return at_ <= size_ ? size_ - at_ : 0; }
  void seek(std::uint64_t to) {
    at_ = to;
    if (to > size_) fail("an offset");
    in_.clear();
    in_.seekg(static_cast<std::streamoff>(to));
  }
  void bytes(void* out, std::size_t n) {
    if (n > left()) fail("a value");
    in_.read(static_cast<char*>(out), static_cast<std::streamsize>(n));
    at_ += n;
  }
  std::uint32_t u32() {
    std::uint32_t v = 0;
    bytes(&v, 4);
    return v;
  }
  std::uint64_t u64() {
    std::uint64_t v = 0;
    bytes(&v, 8);
    return v;
  }
  void skip(std::uint64_t n, const char* what) {
    if (n > left()) fail(std::string(what) + " of " + std::to_string(n) + " bytes");
    seek(at_ + n);
  }
  void string(const char* what) { skip(u32(), what); }
  void metaMap(const char* what) {
    const std::uint32_t count = u32();
    if (count > left() / 12) fail(std::string(what) + " (" + std::to_string(count) + " entries)");
    for (std::uint32_t e = 0; e < count; ++e) {
      string("a metadata name");
      string("a metadata type");
      skip(u32(), "a metadata value");
    }
  }

  std::string name_;
  std::ifstream in_;
  std::uint64_t size_ = 0, at_ = 0;
};

std::function<void(const std::string&)>& vdbPrecheck() {
  static std::function<void(const std::string&)> check;
  return check;
}

}  // namespace

void setVdbPrecheck(std::function<void(const std::string& path)> check) {
  vdbPrecheck() = std::move(check);
}

GridSet readVdb(const std::string& path) {
  initializeOpenVdb();
  requireRegularFile(path, "the OpenVDB file");
  const std::string name = displayName(path);
  VdbLayoutCheck(path, name).run();
  if (vdbPrecheck()) vdbPrecheck()(path);
  GridSet set;
  try {
    openvdb::io::File file(path);
    file.open(/*delayLoad=*/false);
    // The sizes the file declares come first: refuse grids that would not fit before any is
    // read (the stats metadata OpenVDB writes with every grid; writeVdb adds it too).
    openvdb::GridPtrVecPtr heads = file.readAllGridMetadata();
    std::uint64_t declared = 0;
    for (const auto& g : *heads) {
      if (auto m = g->getMetadata<openvdb::Int64Metadata>(openvdb::GridBase::META_FILE_MEM_BYTES))
        declared += static_cast<std::uint64_t>(std::max<openvdb::Int64>(0, m->value()));
    }
    if (declared > kMaxVdbGridBytes)
      throw FileError(name + ": its grids declare " + withThousands(declared) +
                      " bytes in memory; at most " + withThousands(kMaxVdbGridBytes) + " are read");
    file.close();
    // The grids themselves from a stream that throws once the file ends: OpenVDB's readers
    // loop over the counts a file declares, and on a plain stream a damaged count past the
    // end spins through billions of failed reads instead of stopping.
    std::ifstream in(path, std::ios::binary);
    in.exceptions(std::ios::failbit | std::ios::badbit);
    openvdb::io::Stream stream(in, /*delayLoad=*/false);
    openvdb::GridPtrVecPtr grids = stream.getGrids();
    if (openvdb::MetaMap::Ptr meta = stream.getMetadata()) set.impl->fileMetadata = *meta;
    if (grids->empty())
      throw FileError(name + ": the OpenVDB file holds no grids (a truncated or unfinished file?)");
    set.impl->grids = std::move(*grids);
  } catch (const FileError&) {
    throw;
  } catch (const std::ios_base::failure&) {
    throw FileError(name +
                    ": the OpenVDB file ends inside its grids (a truncated or damaged "
                    "file)");
  } catch (const openvdb::Exception& e) {
    throw FileError(name + ": not a readable OpenVDB file (" + e.what() + ")");
  } catch (const std::bad_alloc&) {
    throw FileError(name + ": its grids do not fit in memory");
  } catch (const std::exception& e) {
    throw FileError(name + ": not a readable OpenVDB file (" + e.what() + ")");
  }
  return set;
}

void writeVdb(const GridSet& grids, const std::string& path) {
  initializeOpenVdb();
  AtomicFile out(path);
  try {
    // The stats metadata (voxel count, memory, bounding box) is what readVdb checks first.
    for (const auto& g : grids.impl->grids) g->addStatsMetadata();
    openvdb::io::File file(out.temporaryPath());
    file.write(grids.impl->grids, grids.impl->fileMetadata);
    file.close();
  } catch (const openvdb::Exception& e) {
    throw FileError(displayName(path) + ": cannot write the grids (" + e.what() + ")");
  }
  out.commit();
}

}  // namespace frep
