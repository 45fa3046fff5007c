#pragma once
// The faces of a polyhedron in one flat buffer of vertex indices: two allocations for all of
// them, where a vector per face cost one each (a fracture makes a thousand polyhedra per
// event, and every copy of a primitive copied each face).
#include <cstddef>
#include <functional>
#include <iterator>
#include <span>
#include <stdexcept>
#include <vector>

namespace shatter::geometry {

class FaceList {
public:
    FaceList() = default;
    explicit FaceList(const std::vector<std::vector<int>>& faces) {
        start_.reserve(faces.size() + 1);
        start_.push_back(0);
        for (const auto& face : faces) add(face);
    }
    // The faces of a flat list as a clipper keeps them: face f is indices[start[f] .. start[f + 1]),
    // start[0] == 0 and start.back() == indices.size() (std::invalid_argument otherwise). Two
    // copies at once, where add() per face was a call, an alias check and an insert each
    // (~65 instructions a face, 33k faces in five 64-cell breaks of the 16k shell).
    static FaceList fromFlat(std::span<const int> start, std::span<const int> indices) {
        if (start.empty() ? !indices.empty() : start.front() != 0 || size_t(start.back()) != indices.size())
            throw std::invalid_argument("FaceList::fromFlat: the starts do not cover the indices");
        FaceList list;
        if (start.size() < 2) return list; // no face: start_ stays empty, as a default list's
        list.start_.assign(start.begin(), start.end());
        list.indices_.assign(indices.begin(), indices.end());
        return list;
    }
    // Room for `faces` faces of `indices` vertex indices in all.
    void reserve(size_t faces, size_t indices) {
        start_.reserve(faces + 1);
        indices_.reserve(indices);
    }
    void add(std::span<const int> face) {
        if (start_.empty()) start_.push_back(0);
        // A face of this list (faces.add(faces[i])) is copied first: inserting a vector's own
        // elements into it is undefined once it reallocates.
        if (!face.empty() && !std::less<const int*>{}(face.data(), indices_.data()) &&
            std::less<const int*>{}(face.data(), indices_.data() + indices_.size())) {
            const std::vector<int> copy(face.begin(), face.end());
            add(copy);
            return;
        }
        indices_.insert(indices_.end(), face.begin(), face.end());
        start_.push_back(int(indices_.size()));
    }

    size_t size() const { return start_.empty() ? 0 : start_.size() - 1; }
    bool empty() const { return size() == 0; }
    std::span<const int> operator[](size_t f) const {
        return {indices_.data() + start_[f], size_t(start_[f + 1] - start_[f])};
    }
    // Every face's indices, one after another.
    const std::vector<int>& indices() const { return indices_; }
    // Where each face starts in indices(), then indices().size(): size() + 1 values, none when
    // there is no face. For prefetching: a reader that walks the faces loads these too.
    std::span<const int> starts() const { return start_; }

    // An input iterator over the faces (a face is a span into the list), usable by <algorithm>
    // and std::ranges; `for (const auto& face : faces)` and `for (auto face : faces)` both work.
    class Iterator {
    public:
        using iterator_category = std::input_iterator_tag;
        using value_type = std::span<const int>;
        using difference_type = std::ptrdiff_t;
        using reference = std::span<const int>;
        using pointer = void;
        Iterator() = default;
        Iterator(const FaceList* list, size_t f) : list_(list), f_(f) {}
        std::span<const int> operator*() const { return (*list_)[f_]; }
        Iterator& operator++() {
            ++f_;
            return *this;
        }
        Iterator operator++(int) {
            Iterator before = *this;
            ++f_;
            return before;
        }
        bool operator==(const Iterator& other) const { return f_ == other.f_; }

    private:
        const FaceList* list_ = nullptr;
        size_t f_ = 0;
    };
    Iterator begin() const { return {this, 0}; }
    Iterator end() const { return {this, size()}; }

    bool operator==(const FaceList& other) const {
        return indices_ == other.indices_ && (start_ == other.start_ || size() + other.size() == 0);
    }

private:
    std::vector<int> indices_;
    std::vector<int> start_; // face f is indices_[start_[f] .. start_[f + 1]); empty when there is no face
};

} // namespace shatter::geometry
