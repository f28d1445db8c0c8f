#include "hspline/hs_file.h"

#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <set>
#include <sstream>
#include <vector>

#include "base/atomic_file.h"
#include "base/errors.h"

namespace frep {

namespace {

constexpr int kVersion = 1;
constexpr std::size_t kMaxLineLength = 1 << 16;
constexpr std::size_t kMaxFileBytes = std::size_t(1) << 30;
constexpr long kMaxKnots = 1 << 20;

std::string number(double x) {
  char b[40];
  std::snprintf(b, sizeof b, "%.17g", x);
  return b;
}

// The words of one line, after its comment.
struct Line {
  std::size_t number = 0;
  std::vector<std::string> words;
};

class Reader {
 public:
  Reader(const std::string& text, std::string source) : source_(std::move(source)) {
    std::size_t at = 0, n = 0;
    while (at <= text.size()) {
      std::size_t end = text.find('\n', at);
      if (end == std::string::npos) end = text.size();
      ++n;
      if (end - at > kMaxLineLength)
        fail(n, "the line is longer than " + std::to_string(kMaxLineLength) + " characters");
      std::string line = text.substr(at, end - at);
      if (const auto hash = line.find('#'); hash != std::string::npos) line.resize(hash);
      std::istringstream words(line);
      Line l{n, {}};
      for (std::string w; words >> w;) l.words.push_back(w);
      if (!l.words.empty()) lines_.push_back(std::move(l));
      at = end + 1;
    }
    last_ = n;
  }

  [[noreturn]] void fail(std::size_t line, const std::string& why) const {
    throw FileError(source_ + ", line " + std::to_string(line) + ": " + why);
  }

  // The next line, which must start with `keyword` and have `least` to `most` words after it.
  const Line& expect(const char* keyword, std::size_t least, std::size_t most) {
    if (next_ >= lines_.size())
      fail(last_, std::string("the file ends here, where a '") + keyword +
                      "' line was expected (is it truncated?)");
    const Line& l = lines_[next_++];
    if (l.words[0] != keyword)
      fail(l.number, std::string("'") + keyword + "' expected, found '" + l.words[0] + "'");
    if (l.words.size() - 1 < least || l.words.size() - 1 > most)
      fail(l.number, std::string("'") + keyword + "' takes " +
                         (least == most ? std::to_string(least)
                                        : std::to_string(least) + " to " + std::to_string(most)) +
                         " values, found " + std::to_string(l.words.size() - 1));
    return l;
  }
  bool at(const char* keyword) const {
    return next_ < lines_.size() && lines_[next_].words[0] == keyword;
  }
  bool done() const { return next_ >= lines_.size(); }
  std::size_t lineNumber() const { return next_ < lines_.size() ? lines_[next_].number : last_; }

  double real(const Line& l, std::size_t k, const char* what) const {
    const std::string& w = l.words[k];
    char* end = nullptr;
    errno = 0;
    const double x = std::strtod(w.c_str(), &end);
    if (end != w.c_str() + w.size() || w.empty())
      fail(l.number, std::string(what) + " '" + w + "' is not a number");
    if (!std::isfinite(x) || errno == ERANGE)
      fail(l.number, std::string(what) + " '" + w + "' is not a finite number");
    return x;
  }
  long integer(const Line& l, std::size_t k, const char* what, long lo, long hi) const {
    const std::string& w = l.words[k];
    char* end = nullptr;
    errno = 0;
    const long x = std::strtol(w.c_str(), &end, 10);
    if (end != w.c_str() + w.size() || w.empty() || errno == ERANGE)
      fail(l.number, std::string(what) + " '" + w + "' is not a whole number");
    if (x < lo || x > hi)
      fail(l.number, std::string(what) + " is " + w + "; it must be " + std::to_string(lo) +
                         " to " + std::to_string(hi));
    return x;
  }

 private:
  std::string source_;
  std::vector<Line> lines_;
  std::size_t next_ = 0, last_ = 0;
};

SplineAxis readAxis(Reader& r, const char* name) {
  const Line& a = r.expect("axis", 2, 4);
  if (a.words[1] != name)
    r.fail(a.number,
           std::string("axis ") + name + " expected here, found axis '" + a.words[1] + "'");
  const std::string kind = a.words[2];
  if (kind != "open" && kind != "periodic")
    r.fail(a.number, "an axis is 'open' or 'periodic', not '" + kind + "'");
  const bool periodic = kind == "periodic";
  if (a.words.size() != (periodic ? 5u : 4u))
    r.fail(a.number, periodic ? "a periodic axis gives its CV count and its period"
                              : "an open axis gives its CV count");
  const long count = r.integer(a, 3, "the CV count", 4, kMaxKnots - 4);
  const double period = periodic ? r.real(a, 4, "the period") : 0;
  const std::size_t knots = static_cast<std::size_t>(periodic ? count : count + 4);
  const Line& k = r.expect("knots", knots, knots);
  std::vector<double> values;
  for (std::size_t q = 1; q <= knots; ++q) values.push_back(r.real(k, q, "knot"));
  try {
    return periodic ? SplineAxis::periodic(std::move(values), period)
                    : SplineAxis::open(std::move(values));
  } catch (const ModelError& e) {
    r.fail(k.number, std::string("axis ") + name + ": " + e.what());
  }
}

}  // namespace

std::string hsText(const HSpline& source, bool optimised) {
  HSpline copy;
  const HSpline* h = &source;
  if (optimised) {
    copy = source;
    copy.unrefine();
    h = &copy;
  }
  std::string out = "# FRepCAD hierarchical B-spline (docs/file-formats.md)\nhspline " +
                    std::to_string(kVersion) + "\n";
  const char* names[2] = {"u", "v"};
  for (int d = 0; d < 2; ++d) {
    const SplineAxis& a = d == 0 ? h->level(0).u : h->level(0).v;
    out += std::string("axis ") + names[d] + (a.isPeriodic() ? " periodic " : " open ") +
           std::to_string(a.count());
    if (a.isPeriodic()) out += " " + number(a.period());
    out += "\nknots";
    for (double k : a.knots()) out += " " + number(k);
    out += "\n";
  }
  for (int l = 0; l < h->levelCount(); ++l) {
    out += "level " + std::to_string(l) + " " + std::to_string(h->level(l).cvs.size()) + "\n";
    for (const HsCv& cv : h->level(l).cvs)
      out += "cv " + std::to_string(cv.i) + " " + std::to_string(cv.j) + " " + number(cv.value[0]) +
             " " + number(cv.value[1]) + " " + number(cv.value[2]) + "\n";
  }
  out += "end\n";
  return out;
}

HSpline parseHs(const std::string& text, const std::string& source) {
  if (text.size() > kMaxFileBytes)
    throw FileError(source + ": larger than the 1 GiB an .hs file may have");
  Reader r(text, source);
  const Line& head = r.expect("hspline", 1, 1);
  const long version = r.integer(head, 1, "the version", 0, 1L << 30);
  if (version != kVersion)
    r.fail(head.number, "version " + std::to_string(version) +
                            " is not known; this FRepCAD reads version " +
                            std::to_string(kVersion));
  SplineAxis u = readAxis(r, "u"), v = readAxis(r, "v");
  std::vector<std::vector<HsCv>> levels;
  SplineAxis lu = u, lv = v;
  std::size_t total = 0;
  while (r.at("level")) {
    const Line& l = r.expect("level", 2, 2);
    const long index = r.integer(l, 1, "the level", 0, HSpline::kMaxLevels - 1);
    if (index != static_cast<long>(levels.size()))
      r.fail(l.number, "level " + std::to_string(levels.size()) +
                           " expected here (levels come in order), found level " +
                           std::to_string(index));
    if (index > 0) {
      // A refined axis has at most 2 n + 3 CVs: refuse before its knots are made.
      if ((2 * static_cast<std::size_t>(lu.count()) + 3) *
              (2 * static_cast<std::size_t>(lv.count()) + 3) >
          HSpline::kMaxLevelGrid)
        r.fail(l.number, "level " + std::to_string(index) + "'s CV grid would be larger than the " +
                             std::to_string(HSpline::kMaxLevelGrid) + " allowed");
      lu = lu.refined(), lv = lv.refined();
    }
    const std::size_t expected =
        index == 0 ? static_cast<std::size_t>(lu.count()) * static_cast<std::size_t>(lv.count())
                   : HSpline::kMaxCvs;
    const long count = r.integer(l, 2, "the CV count", 0, static_cast<long>(expected));
    if (index == 0 && static_cast<std::size_t>(count) != expected)
      r.fail(l.number, "level 0 has a CV at every point of its " + std::to_string(lu.count()) +
                           " x " + std::to_string(lv.count()) + " grid: " +
                           std::to_string(expected) + " CVs, not " + std::to_string(count));
    total += static_cast<std::size_t>(count);
    if (total > HSpline::kMaxCvs)
      r.fail(l.number,
             "more than the " + std::to_string(HSpline::kMaxCvs) + " CVs an hspline may have");
    std::vector<HsCv> cvs;
    cvs.reserve(static_cast<std::size_t>(count));
    std::set<std::pair<long, long>> seen;
    for (long c = 0; c < count; ++c) {
      if (!r.at("cv"))
        r.fail(r.lineNumber(), "level " + std::to_string(index) + " declares " +
                                   std::to_string(count) + " CVs but has " + std::to_string(c) +
                                   (r.done() ? " (is the file truncated?)" : ""));
      const Line& cl = r.expect("cv", 5, 5);
      const long i = r.integer(cl, 1, "i", 0, lu.count() - 1);
      const long j = r.integer(cl, 2, "j", 0, lv.count() - 1);
      if (!seen.insert({i, j}).second)
        r.fail(cl.number, hsCvName(int(index), int(i), int(j)) + " is given twice");
      cvs.push_back({int(i), int(j), {r.real(cl, 3, "x"), r.real(cl, 4, "y"), r.real(cl, 5, "z")}});
    }
    levels.push_back(std::move(cvs));
  }
  if (levels.empty()) r.fail(r.lineNumber(), "'level 0' expected");
  r.expect("end", 0, 0);
  if (!r.done()) r.fail(r.lineNumber(), "nothing may follow 'end'");
  try {
    return HSpline::fromLevels(std::move(u), std::move(v), std::move(levels));
  } catch (const ModelError& e) {
    throw FileError(source + ": " + e.what());
  }
}

void writeHsFile(const HSpline& h, const std::string& path, bool optimised) {
  const std::string text = hsText(h, optimised);
  AtomicFile f(path);
  f.write(text.data(), text.size());
  f.commit();
}

HSpline readHsFile(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw FileError(path + ": cannot be opened for reading");
  in.seekg(0, std::ios::end);
  const auto size = static_cast<std::size_t>(in.tellg());
  if (size > kMaxFileBytes) throw FileError(path + ": larger than the 1 GiB an .hs file may have");
  in.seekg(0);
  std::string text(size, '\0');
  in.read(text.data(), static_cast<std::streamsize>(size));
  return parseHs(text, path);
}

}  // namespace frep
