// The only translation unit that includes minizip (zip.h brings zlib's macros along).
#include "io/three_mf_stream.h"

#include <minizip/zip.h>

#include <algorithm>
#include <cerrno>
#include <charconv>
#include <cmath>
#include <condition_variable>
#include <cstring>
#include <ctime>
#include <deque>
#include <memory>
#include <mutex>
#include <stdexcept>
#include <thread>
#include <vector>

#include "base/errors.h"

namespace frep {

namespace {

constexpr const char* kModelPart = "3D/3dmodel.model";
constexpr const char* kContentTypes =
    "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n"
    "<Types xmlns=\"http://schemas.openxmlformats.org/package/2006/content-types\">"
    "<Default Extension=\"rels\" "
    "ContentType=\"application/vnd.openxmlformats-package.relationships+xml\"/>"
    "<Default Extension=\"model\" "
    "ContentType=\"application/vnd.ms-package.3dmanufacturing-3dmodel+xml\"/></Types>\n";
constexpr const char* kRelationships =
    "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n"
    "<Relationships xmlns=\"http://schemas.openxmlformats.org/package/2006/relationships\">"
    "<Relationship Target=\"/3D/3dmodel.model\" Id=\"rel0\" "
    "Type=\"http://schemas.microsoft.com/3dmanufacturing/2013/01/3dmodel\"/></Relationships>\n";
// The model's XML goes to the deflate workers in blocks of this size. (Vertex and triangle
// lines carry no indentation: at tens of millions of lines it would be a tenth of the XML.)
constexpr std::size_t kFlushBytes = 1 << 20;
// Deflate's fastest level: the model's XML is very regular, so it still shrinks about 3x,
// and the merge's other work is not left waiting on the compressor.
constexpr int kDeflateLevel = 1;
// Past this estimate the package takes the zip64 headers (minizip needs to know before the
// entry starts; the true limit is 4 GiB, the margin covers a low estimate).
constexpr std::uint64_t kZip64Above = std::uint64_t(2) << 30;

std::string escapeXml(const std::string& s) {
  std::string out;
  out.reserve(s.size());
  for (char c : s) {
    switch (c) {
      case '&':
        out += "&amp;";
        break;
      case '<':
        out += "&lt;";
        break;
      case '>':
        out += "&gt;";
        break;
      case '"':
        out += "&quot;";
        break;
      default:
        out += c;
    }
  }
  return out;
}

// The shortest decimal that reads back as `v` (std::to_chars' round-trip guarantee).
char* putFloat(char* at, float v) {
  if (v == 0.0f) v = 0.0f;  // no "-0"
  return std::to_chars(at, at + 32, v).ptr;
}

char* putLiteral(char* at, const char* s) {
  const std::size_t n = std::strlen(s);
  std::memcpy(at, s, n);
  return at + n;
}

}  // namespace

// The model's XML, deflated in blocks on every core (deflate was half a brick merge's time
// on one): each block is a raw deflate stream ended by a sync flush, so the blocks laid end
// to end are one deflate stream (as pigz makes them), closed by an empty final block; their
// CRCs combine in order. The entry is written raw into the zip (minizip's raw mode) in block
// order by whichever worker finishes the block at the front. push() hands over a full buffer,
// waiting while enough are in flight; finish() waits for all and returns the size and CRC.
// A write error is thrown from the next push or finish.
struct ThreeMfStreamWriter::Deflater {
  explicit Deflater(void* zip) : zip_(zip) {
    const unsigned cores = std::max(1u, std::min(8u, std::thread::hardware_concurrency()));
    for (unsigned i = 0; i < cores; ++i) workers_.emplace_back([this] { work(); });
    inFlightLimit_ = 2 * cores + 1;
  }
  ~Deflater() {
    {
      std::lock_guard<std::mutex> lock(mutex_);
      stop_ = true;
    }
    changed_.notify_all();
    for (std::thread& t : workers_) t.join();
  }

  // Takes `buffer`'s text and gives back an empty buffer to fill.
  void push(std::string& buffer) {
    auto block = std::make_shared<Block>();
    std::unique_lock<std::mutex> lock(mutex_);
    changed_.wait(lock, [&] { return inOrder_.size() < inFlightLimit_ || error_; });
    if (error_) std::rethrow_exception(error_);
    block->text = std::move(buffer);
    inOrder_.push_back(block);
    todo_.push_back(block);
    if (spare_.empty()) {
      buffer = std::string();
      buffer.reserve(kFlushBytes + 4096);
    } else {
      buffer = std::move(spare_.back());
      spare_.pop_back();
    }
    lock.unlock();
    changed_.notify_all();
  }

  // Waits for every block, writes the final empty block; the XML's size and CRC-32.
  void finish(std::uint64_t& size, unsigned long& crc) {
    std::unique_lock<std::mutex> lock(mutex_);
    changed_.wait(lock, [&] { return inOrder_.empty() || error_; });
    if (error_) std::rethrow_exception(error_);
    // an empty final block: BFINAL set, fixed codes, the end-of-block code
    const unsigned char last[2] = {0x03, 0x00};
    if (zipWriteInFileInZip(zip_, last, 2) != ZIP_OK)
      throw FileError("3MF: write failed: " + std::string(std::strerror(errno)));
    size = size_;
    crc = crc_;
  }

 private:
  struct Block {
    std::string text;
    std::vector<unsigned char> packed;
    unsigned long crc = 0;
    bool done = false;
  };

  void work() {
    z_stream z{};
    if (deflateInit2(&z, kDeflateLevel, Z_DEFLATED, -MAX_WBITS, 8, Z_DEFAULT_STRATEGY) != Z_OK) {
      std::lock_guard<std::mutex> lock(mutex_);
      if (!error_) error_ = std::make_exception_ptr(FileError("3MF: cannot start deflate"));
      changed_.notify_all();
      return;
    }
    std::unique_lock<std::mutex> lock(mutex_);
    for (;;) {
      changed_.wait(lock, [&] { return !todo_.empty() || stop_; });
      if (todo_.empty()) break;  // (stopped)
      std::shared_ptr<Block> b = todo_.front();
      todo_.pop_front();
      lock.unlock();
      compress(z, *b);
      lock.lock();
      b->done = true;
      if (!writing_) writeReady(lock);
      changed_.notify_all();
    }
    deflateEnd(&z);
  }

  static void compress(z_stream& z, Block& b) {
    deflateReset(&z);
    const uLong n = static_cast<uLong>(b.text.size());
    b.crc = crc32(0, reinterpret_cast<const Bytef*>(b.text.data()), static_cast<uInt>(n));
    b.packed.resize(deflateBound(&z, n) + 64);
    z.next_in = reinterpret_cast<Bytef*>(b.text.data());
    z.avail_in = static_cast<uInt>(n);
    z.next_out = b.packed.data();
    z.avail_out = static_cast<uInt>(b.packed.size());
    deflate(&z, Z_SYNC_FLUSH);  // (byte-aligned, not final: the next block follows)
    b.packed.resize(b.packed.size() - z.avail_out);
  }

  // Writes the finished blocks at the front, in order (one writer at a time; the lock is
  // released while writing).
  void writeReady(std::unique_lock<std::mutex>& lock) {
    writing_ = true;
    while (!inOrder_.empty() && inOrder_.front()->done && !error_) {
      std::shared_ptr<Block> b = inOrder_.front();
      lock.unlock();
      const bool ok = zipWriteInFileInZip(zip_, b->packed.data(),
                                          static_cast<unsigned>(b->packed.size())) == ZIP_OK;
      const int err = errno;
      lock.lock();
      if (!ok) {
        error_ = std::make_exception_ptr(
            FileError("3MF: write failed: " + std::string(std::strerror(err))));
        break;
      }
      crc_ = crc32_combine(crc_, b->crc, static_cast<z_off_t>(b->text.size()));
      size_ += b->text.size();
      inOrder_.pop_front();
      b->text.clear();
      spare_.push_back(std::move(b->text));
    }
    writing_ = false;
  }

  void* zip_;
  std::mutex mutex_;
  std::condition_variable changed_;
  std::deque<std::shared_ptr<Block>> inOrder_, todo_;
  std::vector<std::string> spare_;
  std::size_t inFlightLimit_ = 3;
  bool stop_ = false, writing_ = false;
  std::exception_ptr error_;
  std::uint64_t size_ = 0;
  unsigned long crc_ = 0;
  std::vector<std::thread> workers_;
};

const char* lengthUnitXmlName(LengthUnit unit) {
  static const char* names[] = {"micron", "millimeter", "centimeter", "inch", "foot", "meter"};
  return names[static_cast<int>(unit)];
}

std::uint64_t expectedXmlBytes(std::uint64_t vertices, std::uint64_t triangles) {
  // a vertex line at most 3 x 15 characters of number and 25 of markup; a triangle's at
  // most 3 x 10 digits and 30 of markup
  return 4096 + vertices * 70 + triangles * 60;
}

ThreeMfStreamWriter::ThreeMfStreamWriter(const std::string& path, const ThreeMfOptions& options,
                                         std::uint64_t expectedBytes)
    : file_(std::make_unique<AtomicFile>(path)), zip64_(expectedBytes > kZip64Above) {
  // minizip writes files by name: it writes the AtomicFile's temporary, which commit()
  // renames into place as for any other file.
  zip_ = zipOpen64(file_->temporaryPath().c_str(), APPEND_STATUS_CREATE);
  if (!zip_) throw FileError(path + ": cannot start the 3MF package: " + std::strerror(errno));
  spillPath_ = file_->temporaryPath() + ".triangles";
  zip_fileinfo info{};
  const std::time_t now = std::time(nullptr);
  std::tm local{};
  localtime_r(&now, &local);
  info.tmz_date = {static_cast<uInt>(local.tm_sec),  static_cast<uInt>(local.tm_min),
                   static_cast<uInt>(local.tm_hour), static_cast<uInt>(local.tm_mday),
                   static_cast<uInt>(local.tm_mon),  static_cast<uInt>(local.tm_year + 1900)};
  auto smallPart = [&](const char* name, const char* content) {
    if (zipOpenNewFileInZip64(zip_, name, &info, nullptr, 0, nullptr, 0, nullptr, Z_DEFLATED,
                              kDeflateLevel, 0) != ZIP_OK ||
        zipWriteInFileInZip(zip_, content, static_cast<unsigned>(std::strlen(content))) != ZIP_OK ||
        zipCloseFileInZip(zip_) != ZIP_OK)
      throw FileError(path + ": cannot write the 3MF package's part " + name);
  };
  smallPart("[Content_Types].xml", kContentTypes);
  smallPart("_rels/.rels", kRelationships);
  // raw: the Deflater makes the deflate stream
  if (zipOpenNewFileInZip3_64(zip_, kModelPart, &info, nullptr, 0, nullptr, 0, nullptr, Z_DEFLATED,
                              kDeflateLevel, 1, -MAX_WBITS, 8, Z_DEFAULT_STRATEGY, nullptr, 0,
                              zip64_ ? 1 : 0) != ZIP_OK)
    throw FileError(path + ": cannot write the 3MF package's model");
  std::string head =
      "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n<model unit=\"" +
      std::string(lengthUnitXmlName(options.unit)) +
      "\" xml:lang=\"en-US\" "
      "xmlns=\"http://schemas.microsoft.com/3dmanufacturing/core/2015/02\"" +
      std::string(options.beamLattice ? " xmlns:b=\"http://schemas.microsoft.com/3dmanufacturing/"
                                        "beamlattice/2017/02\" requiredextensions=\"b\""
                                      : "") +
      ">\n";
  beamLattice_ = options.beamLattice;
  for (const auto& [key, value] : options.metadata)
    head += " <metadata name=\"" + escapeXml(key) + "\">" + escapeXml(value) + "</metadata>\n";
  head += " <resources>\n";
  buffer_.reserve(kFlushBytes + 4096);
  deflater_ = std::make_unique<Deflater>(zip_);
  text(head);
}

ThreeMfStreamWriter::~ThreeMfStreamWriter() {
  deflater_.reset();  // (stops the thread before the zip closes)
  if (spill_) std::fclose(spill_);
  if (!spillPath_.empty()) std::remove(spillPath_.c_str());
  if (zip_) zipClose(zip_, nullptr);  // (the temporary is removed with file_)
}

void ThreeMfStreamWriter::text(const char* data, std::size_t size) {
  buffer_.append(data, size);
  if (buffer_.size() >= kFlushBytes) flush();
}

void ThreeMfStreamWriter::flush() {
  if (buffer_.empty()) return;
  written_ += buffer_.size();
  deflater_->push(buffer_);
  if (!zip64_ && written_ >= 0xFFFFFFF0ull)
    throw FileError(
        "3MF: the model grew past 4 GiB without the zip64 headers its size "
        "estimate should have asked for");
}

void ThreeMfStreamWriter::beginObject(const std::string& name, bool buildItem) {
  if (inObject_) throw std::logic_error("ThreeMfStreamWriter: an object is still open");
  inObject_ = true;
  verticesClosed_ = trianglesOpen_ = objectBeams_ = false;
  buildItems_.push_back(buildItem);
  objectName_ = name;
  vertices_ = spilled_ = objectTriangles_ = 0;
  ++objects_;
  text("  <object id=\"" + std::to_string(objects_) + "\" type=\"model\"" +
       (name.empty() ? std::string() : " name=\"" + escapeXml(name) + "\"") +
       ">\n   <mesh>\n    <vertices>\n");
}

void ThreeMfStreamWriter::vertex(const Vec3f& p) {
  if (!inObject_ || verticesClosed_)
    throw std::logic_error("ThreeMfStreamWriter: no object takes vertices");
  if (!std::isfinite(p[0]) || !std::isfinite(p[1]) || !std::isfinite(p[2]))
    throw FileError("3MF object '" + objectName_ + "' has vertices with non-finite coordinates");
  if (vertices_ >= 0xFFFFFFF0ull)
    throw FileError("3MF object '" + objectName_ + "' has too many vertices for 3MF");
  char line[160];
  char* at = putLiteral(line, "<vertex x=\"");
  at = putFloat(at, p[0]);
  at = putLiteral(at, "\" y=\"");
  at = putFloat(at, p[1]);
  at = putLiteral(at, "\" z=\"");
  at = putFloat(at, p[2]);
  at = putLiteral(at, "\"/>\n");
  text(line, static_cast<std::size_t>(at - line));
  ++vertices_;
}

void ThreeMfStreamWriter::writeTriangle(const Triangle& t) {
  for (std::uint32_t v : t)
    if (v >= vertices_)
      throw FileError("3MF object '" + objectName_ + "': a triangle refers to vertex " +
                      std::to_string(v) + " of " + std::to_string(vertices_));
  if (t[0] == t[1] || t[1] == t[2] || t[0] == t[2])
    throw FileError("3MF object '" + objectName_ + "': a triangle names vertex " +
                    std::to_string(t[0] == t[1] ? t[0] : t[2]) +
                    " twice, which the 3MF core specification forbids");
  if (!trianglesOpen_) {
    text("    <triangles>\n");
    trianglesOpen_ = true;
  }
  char line[128];
  char* at = putLiteral(line, "<triangle v1=\"");
  at = std::to_chars(at, at + 10, t[0]).ptr;
  at = putLiteral(at, "\" v2=\"");
  at = std::to_chars(at, at + 10, t[1]).ptr;
  at = putLiteral(at, "\" v3=\"");
  at = std::to_chars(at, at + 10, t[2]).ptr;
  at = putLiteral(at, "\"/>\n");
  text(line, static_cast<std::size_t>(at - line));
}

void ThreeMfStreamWriter::triangle(const Triangle& t) {
  if (!inObject_) throw std::logic_error("ThreeMfStreamWriter: no object is open");
  if (++objectTriangles_ > 0xFFFFFFF0ull)
    throw FileError("3MF object '" + objectName_ + "' has too many triangles for 3MF");
  ++trianglesTotal_;
  if (verticesClosed_) return writeTriangle(t);
  if (!spill_) {
    spill_ = std::fopen(spillPath_.c_str(), "w+b");
    if (!spill_)
      throw FileError(spillPath_ +
                      ": cannot hold the triangles for the 3MF: " + std::strerror(errno));
  }
  if (std::fwrite(t.data(), sizeof(Triangle), 1, spill_) != 1)
    throw FileError(spillPath_ + ": write failed: " + std::strerror(errno));
  ++spilled_;
}

void ThreeMfStreamWriter::closeVertices() {
  if (verticesClosed_) return;
  verticesClosed_ = true;
  text("    </vertices>\n");
  if (!spill_) return;
  // the triangles that came before the last vertex, in their order
  if (std::fflush(spill_) != 0 || std::fseek(spill_, 0, SEEK_SET) != 0)
    throw FileError(spillPath_ + ": read failed: " + std::strerror(errno));
  std::vector<Triangle> chunk(1 << 16);
  for (std::uint64_t left = spilled_; left > 0;) {
    const std::size_t n = static_cast<std::size_t>(std::min<std::uint64_t>(left, chunk.size()));
    if (std::fread(chunk.data(), sizeof(Triangle), n, spill_) != n)
      throw FileError(spillPath_ + ": read failed: " + std::strerror(errno));
    for (std::size_t i = 0; i < n; ++i) writeTriangle(chunk[i]);
    left -= n;
  }
  std::fclose(spill_);
  spill_ = nullptr;
  std::remove(spillPath_.c_str());
  spilled_ = 0;
}

void ThreeMfStreamWriter::beams(const BeamLattice3mf& lattice) {
  if (!inObject_) throw std::logic_error("ThreeMfStreamWriter: no object is open");
  if (!beamLattice_) throw std::logic_error("ThreeMfStreamWriter: beams need options.beamLattice");
  closeVertices();
  if (trianglesOpen_) text("    </triangles>\n");
  trianglesOpen_ = false;
  if (!(lattice.radius > 0.0) || !std::isfinite(lattice.radius) || !(lattice.minLength > 0.0))
    throw FileError("3MF object '" + objectName_ +
                    "': a beam lattice needs a radius and a "
                    "shortest beam length > 0");
  if (lattice.clippingObject >= objects_)
    throw FileError("3MF object '" + objectName_ +
                    "': its beams' clipping mesh must be an "
                    "earlier object");
  char number[32];
  auto real = [&](double v) {
    return std::string(number, std::to_chars(number, number + sizeof number, v).ptr);
  };
  std::string head = "    <b:beamlattice radius=\"" + real(lattice.radius) + "\" minlength=\"" +
                     real(lattice.minLength) + "\"";
  // (the specification's draft, which lib3mf 1.8 reads, named the mode `clipping`; its
  // release `clippingmode`: both are written)
  if (lattice.clippingObject)
    head += " clipping=\"inside\" clippingmode=\"inside\" clippingmesh=\"" +
            std::to_string(lattice.clippingObject) + "\"";
  text(head + ">\n     <b:beams>\n");
  for (const Beam3mf& beam : lattice.beams) {
    if (beam.v1 >= vertices_ || beam.v2 >= vertices_ || beam.v1 == beam.v2)
      throw FileError("3MF object '" + objectName_ + "': a beam joins vertices " +
                      std::to_string(beam.v1) + " and " + std::to_string(beam.v2) + " of " +
                      std::to_string(vertices_));
    std::string line =
        "<b:beam v1=\"" + std::to_string(beam.v1) + "\" v2=\"" + std::to_string(beam.v2) + "\"";
    if (beam.r1 > 0.0) line += " r1=\"" + real(beam.r1) + "\"";
    if (beam.r2 > 0.0) line += " r2=\"" + real(beam.r2) + "\"";
    text(line + "/>\n");
  }
  text("     </b:beams>\n    </b:beamlattice>\n");
  objectBeams_ = !lattice.beams.empty();
}

void ThreeMfStreamWriter::endObject() {
  if (!inObject_) throw std::logic_error("ThreeMfStreamWriter: no object is open");
  closeVertices();
  if (objectTriangles_ == 0 && !objectBeams_)
    throw FileError("3MF object '" + objectName_ + "' has no triangles");
  if (trianglesOpen_) text("    </triangles>\n");
  trianglesOpen_ = false;
  text("   </mesh>\n  </object>\n");
  inObject_ = false;
}

void ThreeMfStreamWriter::addObject(const std::string& name, const TriangleMesh& mesh,
                                    const std::function<void(std::size_t)>& written) {
  constexpr std::size_t kChunk = 1 << 16;  // items between two calls of `written`
  beginObject(name);
  for (std::size_t i = 0; i < mesh.positions.size(); ++i) {
    vertex(mesh.positions[i]);
    if (written && (i + 1) % kChunk == 0) written(kChunk);
  }
  if (written) written(mesh.positions.size() % kChunk);
  closeVertices();
  for (std::size_t i = 0; i < mesh.triangles.size(); ++i) {
    triangle(mesh.triangles[i]);
    if (written && (i + 1) % kChunk == 0) written(kChunk);
  }
  if (written) written(mesh.triangles.size() % kChunk);
  endObject();
}

std::unique_ptr<AtomicFile> ThreeMfStreamWriter::finish() {
  if (inObject_) endObject();
  if (objects_ == 0) throw FileError("3MF: no objects to write");
  std::string tail = " </resources>\n <build>\n";
  for (std::uint32_t id = 1; id <= objects_; ++id)
    if (buildItems_[id - 1]) tail += "  <item objectid=\"" + std::to_string(id) + "\"/>\n";
  tail += " </build>\n</model>\n";
  text(tail);
  flush();
  std::uint64_t size = 0;
  unsigned long crc = 0;
  deflater_->finish(size, crc);
  deflater_.reset();
  void* zip = zip_;
  zip_ = nullptr;
  const int closedEntry = zipCloseFileInZipRaw64(zip, size, crc);
  if (zipClose(zip, nullptr) != ZIP_OK || closedEntry != ZIP_OK)
    throw FileError("3MF: cannot finish the package: " + std::string(std::strerror(errno)));
  return std::move(file_);
}

}  // namespace frep
