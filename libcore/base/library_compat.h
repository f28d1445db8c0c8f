#pragma once
// Where the library versions of the two supported platforms differ in API (Debian bookworm:
// nanoflann 1.4, CGAL 5.5; trixie: nanoflann 1.5, CGAL 6.0), the difference is bridged here
// and nowhere else. Each part is compiled only where its library's header was included
// first, so a file that uses neither library pulls in neither.

#include <cstdint>
#include <utility>

namespace frep {

#ifdef NANOFLANN_VERSION
// nanoflann 1.5 renamed SearchParams (checks, eps, sorted) to SearchParameters (eps, sorted)
// and returns radius matches as ResultItem instead of std::pair; both have .first / .second.
#if NANOFLANN_VERSION >= 0x150
using KdRadiusMatch = nanoflann::ResultItem<std::uint32_t, double>;
inline nanoflann::SearchParameters kdUnsortedSearch() { return nanoflann::SearchParameters(0, false); }
#else
using KdRadiusMatch = std::pair<std::uint32_t, double>;
inline nanoflann::SearchParams kdUnsortedSearch() { return nanoflann::SearchParams(32, 0, false); }
#endif
#endif  // NANOFLANN_VERSION

#ifdef CGAL_VERSION_NR
// CGAL 6 returns std::variant from intersections (the AABB tree's too); CGAL 5 boost::variant.
template <class T, class Variant>
const T* intersectionAs(const Variant& v) {
#if CGAL_VERSION_NR >= 1060000000
  return std::get_if<T>(&v);
#else
  return boost::get<T>(&v);
#endif
}
#endif  // CGAL_VERSION_NR

}  // namespace frep
