#pragma once
/// \file
/// Standard-library containers in archives.
///
/// Encoding:
///  - vector, list, deque, set, multiset, unordered_set: u32 count, then the
///    elements (vector<bool>: one byte 0/1 per element);
///  - map, multimap, unordered_map: u32 count, then key, value per entry;
///  - pair: first, second; tuple: its elements in order;
///  - array<T, N>: u32 N (checked on load), then the elements;
///  - optional: bool (one byte), then the value if present.
/// Unordered containers are written in their iteration order, so their bytes
/// may differ between runs; their content round-trips. Loading a set, map or
/// unordered container rejects duplicate keys with rove::ParseError.

#include <array>
#include <cstdint>
#include <deque>
#include <list>
#include <memory>
#include <map>
#include <optional>
#include <set>
#include <tuple>
#include <unordered_map>
#include <unordered_set>
#include <utility>
#include <vector>

#include "rove/serialization/archive.h"

namespace rove {

/// Counts take 4 bytes.
template <typename T, typename A>
struct SerializedMinSize<std::vector<T, A>> {
  /// The u32 count.
  static constexpr std::uint64_t value = 4;
};
/// Counts take 4 bytes.
template <typename T, typename A>
struct SerializedMinSize<std::list<T, A>> {
  /// The u32 count.
  static constexpr std::uint64_t value = 4;
};
/// Counts take 4 bytes.
template <typename T, typename A>
struct SerializedMinSize<std::deque<T, A>> {
  /// The u32 count.
  static constexpr std::uint64_t value = 4;
};
/// Counts take 4 bytes.
template <typename K, typename C, typename A>
struct SerializedMinSize<std::set<K, C, A>> {
  /// The u32 count.
  static constexpr std::uint64_t value = 4;
};
/// Counts take 4 bytes.
template <typename K, typename C, typename A>
struct SerializedMinSize<std::multiset<K, C, A>> {
  /// The u32 count.
  static constexpr std::uint64_t value = 4;
};
/// Counts take 4 bytes.
template <typename K, typename H, typename E, typename A>
struct SerializedMinSize<std::unordered_set<K, H, E, A>> {
  /// The u32 count.
  static constexpr std::uint64_t value = 4;
};
/// Counts take 4 bytes.
template <typename K, typename V, typename C, typename A>
struct SerializedMinSize<std::map<K, V, C, A>> {
  /// The u32 count.
  static constexpr std::uint64_t value = 4;
};
/// Counts take 4 bytes.
template <typename K, typename V, typename C, typename A>
struct SerializedMinSize<std::multimap<K, V, C, A>> {
  /// The u32 count.
  static constexpr std::uint64_t value = 4;
};
/// Counts take 4 bytes.
template <typename K, typename V, typename H, typename E, typename A>
struct SerializedMinSize<std::unordered_map<K, V, H, E, A>> {
  /// The u32 count.
  static constexpr std::uint64_t value = 4;
};
/// Both members.
template <typename A, typename B>
struct SerializedMinSize<std::pair<A, B>> {
  /// Sum of the members' minima.
  static constexpr std::uint64_t value = SerializedMinSize<A>::value + SerializedMinSize<B>::value;
};
/// All members.
template <typename... Ts>
struct SerializedMinSize<std::tuple<Ts...>> {
  /// Sum of the members' minima.
  static constexpr std::uint64_t value = (std::uint64_t{0} + ... + SerializedMinSize<Ts>::value);
};
/// Count plus N elements.
template <typename T, std::size_t N>
struct SerializedMinSize<std::array<T, N>> {
  /// The u32 count and the elements' minima.
  static constexpr std::uint64_t value = 4 + N * SerializedMinSize<T>::value;
};
/// The presence flag.
template <typename T>
struct SerializedMinSize<std::optional<T>> {
  /// One byte.
  static constexpr std::uint64_t value = 1;
};

namespace detail {

template <typename Range>
void save_elements(OutArchive& ar, const Range& r, std::string_view field) {
  ar.write_length(r.size(), field);
  for (const auto& e : r) save(ar, e);
}

template <typename Container>
void load_sequence(InArchive& ar, Container& c, std::string_view field) {
  using T = typename Container::value_type;
  c.clear();
  const std::uint32_t n = ar.read_length(field, SerializedMinSize<T>::value);
  for (std::uint32_t i = 0; i < n; ++i) {
    T e{};
    load(ar, e);
    c.push_back(std::move(e));
  }
}

template <typename Set>
void load_set(InArchive& ar, Set& s, std::string_view field, bool unique) {
  using K = typename Set::value_type;
  s.clear();
  const std::uint32_t n = ar.read_length(field, SerializedMinSize<K>::value);
  for (std::uint32_t i = 0; i < n; ++i) {
    const std::uint64_t at = ar.offset();
    K k{};
    load(ar, k);
    s.insert(std::move(k));
    if (unique && s.size() != i + 1) ar.fail_at(at, field, "duplicate key");
  }
}

template <typename Map>
void load_map(InArchive& ar, Map& m, std::string_view field, bool unique) {
  using K = typename Map::key_type;
  using V = typename Map::mapped_type;
  m.clear();
  const std::uint32_t n =
      ar.read_length(field, SerializedMinSize<K>::value + SerializedMinSize<V>::value);
  for (std::uint32_t i = 0; i < n; ++i) {
    const std::uint64_t at = ar.offset();
    K k{};
    V v{};
    load(ar, k);
    load(ar, v);
    m.emplace(std::move(k), std::move(v));
    if (unique && m.size() != i + 1) ar.fail_at(at, field, "duplicate key");
  }
}

}  // namespace detail

/// Writes a vector: u32 count, then the elements (scalars in one block).
template <typename T, typename A>
void save(OutArchive& ar, const std::vector<T, A>& v) {
  if constexpr (FixedScalar<T> && !std::same_as<T, bool>) {
    ar.write_length(v.size(), "vector");
    ar.write_scalars(std::span<const T>(v.data(), v.size()));
  } else {
    detail::save_elements(ar, v, "vector");
  }
}
/// Reads a vector written by save.
template <typename T, typename A>
void load(InArchive& ar, std::vector<T, A>& v) {
  if constexpr (FixedScalar<T> && !std::same_as<T, bool>) {
    v.clear();
    const std::uint32_t n = ar.read_length("vector", sizeof(T));
    if constexpr (std::same_as<A, std::allocator<T>>) {
      ar.append_scalars(v, n, "vector");
    } else {
      std::vector<T> tmp;
      ar.append_scalars(tmp, n, "vector");
      v.assign(tmp.begin(), tmp.end());
    }
  } else {
    detail::load_sequence(ar, v, "vector");
  }
}

/// Writes a list: u32 count, then the elements.
template <typename T, typename A>
void save(OutArchive& ar, const std::list<T, A>& l) {
  detail::save_elements(ar, l, "list");
}
/// Reads a list written by save.
template <typename T, typename A>
void load(InArchive& ar, std::list<T, A>& l) {
  detail::load_sequence(ar, l, "list");
}

/// Writes a deque: u32 count, then the elements.
template <typename T, typename A>
void save(OutArchive& ar, const std::deque<T, A>& d) {
  detail::save_elements(ar, d, "deque");
}
/// Reads a deque written by save.
template <typename T, typename A>
void load(InArchive& ar, std::deque<T, A>& d) {
  detail::load_sequence(ar, d, "deque");
}

/// Writes a set: u32 count, then the keys in order.
template <typename K, typename C, typename A>
void save(OutArchive& ar, const std::set<K, C, A>& s) {
  detail::save_elements(ar, s, "set");
}
/// Reads a set; a repeated key is a ParseError.
template <typename K, typename C, typename A>
void load(InArchive& ar, std::set<K, C, A>& s) {
  detail::load_set(ar, s, "set", true);
}

/// Writes a multiset: u32 count, then the keys in order.
template <typename K, typename C, typename A>
void save(OutArchive& ar, const std::multiset<K, C, A>& s) {
  detail::save_elements(ar, s, "multiset");
}
/// Reads a multiset written by save.
template <typename K, typename C, typename A>
void load(InArchive& ar, std::multiset<K, C, A>& s) {
  detail::load_set(ar, s, "multiset", false);
}

/// Writes an unordered_set: u32 count, then the keys in iteration order.
template <typename K, typename H, typename E, typename A>
void save(OutArchive& ar, const std::unordered_set<K, H, E, A>& s) {
  detail::save_elements(ar, s, "unordered_set");
}
/// Reads an unordered_set; a repeated key is a ParseError.
template <typename K, typename H, typename E, typename A>
void load(InArchive& ar, std::unordered_set<K, H, E, A>& s) {
  detail::load_set(ar, s, "unordered_set", true);
}

/// Writes a map: u32 count, then key, value per entry in key order.
template <typename K, typename V, typename C, typename A>
void save(OutArchive& ar, const std::map<K, V, C, A>& m) {
  ar.write_length(m.size(), "map");
  for (const auto& [k, v] : m) {
    save(ar, k);
    save(ar, v);
  }
}
/// Reads a map; a repeated key is a ParseError.
template <typename K, typename V, typename C, typename A>
void load(InArchive& ar, std::map<K, V, C, A>& m) {
  detail::load_map(ar, m, "map", true);
}

/// Writes a multimap: u32 count, then key, value per entry in order.
template <typename K, typename V, typename C, typename A>
void save(OutArchive& ar, const std::multimap<K, V, C, A>& m) {
  ar.write_length(m.size(), "multimap");
  for (const auto& [k, v] : m) {
    save(ar, k);
    save(ar, v);
  }
}
/// Reads a multimap written by save (equal keys keep their order).
template <typename K, typename V, typename C, typename A>
void load(InArchive& ar, std::multimap<K, V, C, A>& m) {
  detail::load_map(ar, m, "multimap", false);
}

/// Writes an unordered_map: u32 count, then key, value in iteration order.
template <typename K, typename V, typename H, typename E, typename A>
void save(OutArchive& ar, const std::unordered_map<K, V, H, E, A>& m) {
  ar.write_length(m.size(), "unordered_map");
  for (const auto& [k, v] : m) {
    save(ar, k);
    save(ar, v);
  }
}
/// Reads an unordered_map; a repeated key is a ParseError.
template <typename K, typename V, typename H, typename E, typename A>
void load(InArchive& ar, std::unordered_map<K, V, H, E, A>& m) {
  detail::load_map(ar, m, "unordered_map", true);
}

/// Writes a pair: first, then second.
template <typename A, typename B>
void save(OutArchive& ar, const std::pair<A, B>& p) {
  save(ar, p.first);
  save(ar, p.second);
}
/// Reads a pair written by save.
template <typename A, typename B>
void load(InArchive& ar, std::pair<A, B>& p) {
  load(ar, p.first);
  load(ar, p.second);
}

/// Writes a tuple: its elements in order.
template <typename... Ts>
void save(OutArchive& ar, const std::tuple<Ts...>& t) {
  std::apply([&ar](const auto&... e) { (save(ar, e), ...); }, t);
}
/// Reads a tuple written by save.
template <typename... Ts>
void load(InArchive& ar, std::tuple<Ts...>& t) {
  std::apply([&ar](auto&... e) { (load(ar, e), ...); }, t);
}

/// Writes an array: u32 N, then the elements.
template <typename T, std::size_t N>
void save(OutArchive& ar, const std::array<T, N>& a) {
  detail::save_elements(ar, a, "array");
}
/// Reads an array; a stored count other than N is a ParseError.
template <typename T, std::size_t N>
void load(InArchive& ar, std::array<T, N>& a) {
  const std::uint64_t at = ar.offset();
  const auto n = ar.read_scalar<std::uint32_t>("array");
  if (n != N) {
    ar.fail_at(at, "array",
               "stored " + std::to_string(n) + " elements, expected " + std::to_string(N));
  }
  for (auto& e : a) load(ar, e);
}

/// Writes an optional: a bool, then the value if present.
template <typename T>
void save(OutArchive& ar, const std::optional<T>& o) {
  ar.write_scalar(o.has_value());
  if (o) save(ar, *o);
}
/// Reads an optional written by save.
template <typename T>
void load(InArchive& ar, std::optional<T>& o) {
  if (ar.read_scalar<bool>("optional")) {
    T v{};
    load(ar, v);
    o = std::move(v);
  } else {
    o.reset();
  }
}

}  // namespace rove
