// Named views of packed parameter vectors. A solver sees one flat vector; the code that packs or reads it
// names each part once, in a layout that allots spans in order, and then indexes through the spans only
// (no bare offsets such as z[1 + 2 * k + i]).
#pragma once

#include <Eigen/Core>

namespace gyrosid {

// A contiguous part of a packed vector: `size` entries from `offset` (size 0: the part is absent).
struct Span {
  Eigen::Index offset = 0, size = 0;
  bool present() const { return size > 0; }
  Eigen::Index at(Eigen::Index i) const { return offset + i; }  // the part's i-th entry, in the whole vector
  template <typename Vector>
  auto of(Vector& v) const {
    return v.segment(offset, size);
  }
};

// Allots spans one after another; size() is the packed vector's length so far.
class SpanPacker {
 public:
  Span take(Eigen::Index n) {
    const Span s{next_, n};
    next_ += n;
    return s;
  }
  Span take_if(bool wanted, Eigen::Index n) { return take(wanted ? n : 0); }
  Eigen::Index size() const { return next_; }

 private:
  Eigen::Index next_ = 0;
};

}  // namespace gyrosid
