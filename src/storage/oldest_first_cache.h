// A map whose entries are dropped oldest first beyond a byte bound: the LTM's words stored lately
// (long_term_memory.h) and the rows read ahead of retrieval (ltm_read_ahead.h). Not thread-safe:
// its owner locks.
#pragma once

#include <cstddef>
#include <iterator>
#include <list>
#include <optional>
#include <unordered_map>
#include <utility>

namespace memloop {

template <typename Key, typename Value>
class OldestFirstCache {
 public:
  explicit OldestFirstCache(size_t max_bytes) : max_bytes_(max_bytes) {}

  // Adds `value` (`bytes` of memory) as the newest, replacing an entry of the same key; then drops
  // the oldest, calling `dropped(key, value)` for each, while the bound is exceeded (the newest
  // stays, whatever its size).
  template <typename Dropped>
  void Add(const Key& key, Value value, size_t bytes, Dropped dropped) {
    Erase(key);
    order_.push_back(key);
    entries_.emplace(key, Entry{std::move(value), bytes, std::prev(order_.end())});
    bytes_ += bytes;
    while (bytes_ > max_bytes_ && entries_.size() > 1) {
      const auto oldest = entries_.find(order_.front());
      dropped(oldest->first, oldest->second.value);
      Erase(oldest);
    }
  }
  void Add(const Key& key, Value value, size_t bytes) {
    Add(key, std::move(value), bytes, [](const Key&, const Value&) {});
  }
  // Null when absent.
  const Value* Find(const Key& key) const {
    const auto entry = entries_.find(key);
    return entry == entries_.end() ? nullptr : &entry->second.value;
  }
  bool Contains(const Key& key) const { return entries_.count(key) > 0; }
  // Removes the entry and gives its value; nullopt when absent.
  std::optional<Value> Take(const Key& key) {
    const auto entry = entries_.find(key);
    if (entry == entries_.end()) return std::nullopt;
    std::optional<Value> value(std::move(entry->second.value));
    Erase(entry);
    return value;
  }
  void Erase(const Key& key) {
    const auto entry = entries_.find(key);
    if (entry != entries_.end()) Erase(entry);
  }
  size_t bytes() const { return bytes_; }
  size_t size() const { return entries_.size(); }

 private:
  struct Entry {
    Value value;
    size_t bytes;
    typename std::list<Key>::iterator order;  // in order_
  };
  using Entries = std::unordered_map<Key, Entry>;

  void Erase(typename Entries::iterator entry) {
    bytes_ -= entry->second.bytes;
    order_.erase(entry->second.order);
    entries_.erase(entry);
  }

  size_t max_bytes_;
  size_t bytes_ = 0;
  std::list<Key> order_;  // keys, oldest first
  Entries entries_;
};

}  // namespace memloop
