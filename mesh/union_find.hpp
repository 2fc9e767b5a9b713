#pragma once
// Disjoint sets over 0..n-1 with path halving. The smaller index becomes the
// root, so a component's root is its first member and results do not depend
// on the order of unions.

#include <algorithm>
#include <numeric>
#include <vector>

namespace lhr {

class UnionFind {
 public:
  explicit UnionFind(std::size_t n) : parent_(n) { std::iota(parent_.begin(), parent_.end(), 0); }

  int find(int x) {
    while (parent_[x] != x) {
      parent_[x] = parent_[parent_[x]];
      x = parent_[x];
    }
    return x;
  }

  void unite(int a, int b) {
    a = find(a);
    b = find(b);
    if (a != b) parent_[std::max(a, b)] = std::min(a, b);
  }

 private:
  std::vector<int> parent_;
};

}  // namespace lhr
