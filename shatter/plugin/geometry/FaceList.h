#pragma once
// The faces of a polyhedron in one flat buffer of vertex indices, with where each face starts:
// one allocation for all of them (a fracture makes a thousand polyhedra per event). Copies
// share the buffer, which is never written while shared: a copy of a polyhedron copies no
// face, and add() to a shared list first copies it into a buffer of its own.
#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <iterator>
#include <memory>
#include <span>
#include <stdexcept>
#include <utility>
#include <vector>

namespace shatter::geometry {

class FaceList {
public:
    FaceList() = default;
    explicit FaceList(const std::vector<std::vector<int>>& faces) {
        size_t indices = 0;
        for (const auto& face : faces) indices += face.size();
        reserve(faces.size(), indices);
        for (const auto& face : faces) add(face);
    }
    // Copies share the buffer (see above); a moved-from list has no buffer, so no face. The
    // defaults: a polyhedron's move is its members' (a move that emptied six members by hand
    // made ConvexPolyhedron's move 1.5 % of a 16k-shell break's time profile, poly16).

    // The faces of a flat list as a clipper keeps them: face f is indices[start[f] .. start[f + 1]),
    // start[0] == 0 and start.back() == indices.size() (std::invalid_argument otherwise). Two
    // copies at once, where add() per face was a call, an alias check and an insert each
    // (~65 instructions a face, 33k faces in five 64-cell breaks of the 16k shell).
    static FaceList fromFlat(std::span<const int> start, std::span<const int> indices) {
        if (start.empty() ? !indices.empty() : start.front() != 0 || size_t(start.back()) != indices.size())
            throw std::invalid_argument("FaceList::fromFlat: the starts do not cover the indices");
        FaceList list;
        if (start.size() < 2) return list; // no face: no buffer, as a default list's
        list.regrow(start.size() - 1, indices.size());
        std::copy(start.begin(), start.end(), list.buffer_.get() + kHeader);
        std::copy(indices.begin(), indices.end(), list.indices_);
        list.buffer_[kFaces] = int(start.size() - 1);
        list.buffer_[kIndexCount] = int(indices.size());
        return list;
    }
    // Room for `faces` faces of `indices` vertex indices in all, in a buffer of this list's own.
    void reserve(size_t faces, size_t indices) {
        if (faces + indices == 0 && !buffer_) return; // nothing to hold: no buffer
        if (!ownsAlone() || faces > room(kFaceRoom) || indices > room(kIndexRoom))
            regrow(std::max(faces, room(kFaceRoom)), std::max(indices, room(kIndexRoom)));
    }
    void add(std::span<const int> face) {
        const size_t faces = size() + 1, indices = indexCount() + face.size();
        // The old buffer is kept until the face is copied: it may be a face of this list
        // (faces.add(faces[i])) or of a list sharing its buffer.
        std::shared_ptr<int[]> old;
        if (!ownsAlone() || faces > room(kFaceRoom) || indices > room(kIndexRoom)) {
            old = buffer_;
            regrow(std::max(faces, 2 * room(kFaceRoom)), std::max(indices, 2 * room(kIndexRoom)));
        }
        int* header = buffer_.get();
        std::copy(face.begin(), face.end(), indices_ + header[kIndexCount]); // (behind the list's indices)
        header[kFaces] = int(faces);
        header[kIndexCount] = int(indices);
        header[kHeader + faces] = int(indices);
    }

    size_t size() const { return buffer_ ? size_t(buffer_[kFaces]) : 0; }
    bool empty() const { return size() == 0; }
    std::span<const int> operator[](size_t f) const {
        const int* start = buffer_.get() + kHeader;
        return {indices_ + start[f], size_t(start[f + 1] - start[f])};
    }
    // Every face's indices, one after another.
    std::span<const int> indices() const { return buffer_ ? std::span<const int>(indices_, indexCount()) : std::span<const int>(); }
    // Where each face starts in indices(), then indices().size(): size() + 1 values, none when
    // there is no face. For prefetching: a reader that walks the faces loads these too.
    std::span<const int> starts() const {
        const size_t faces = size();
        return faces == 0 ? std::span<const int>() : std::span<const int>(buffer_.get() + kHeader, faces + 1);
    }

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
        return std::ranges::equal(starts(), other.starts()) && std::ranges::equal(indices(), other.indices());
    }

private:
    // The buffer: a header (the face count, the index count, the room for faces and for
    // indices), the starts (room for faces + 1: face f is indices_[start[f] .. start[f + 1])),
    // then the indices.
    static constexpr size_t kFaces = 0, kIndexCount = 1, kFaceRoom = 2, kIndexRoom = 3, kHeader = 4;

    size_t indexCount() const { return buffer_ ? size_t(buffer_[kIndexCount]) : 0; }
    size_t room(size_t field) const { return buffer_ ? size_t(buffer_[field]) : 0; }
    bool ownsAlone() const { return buffer_ && buffer_.use_count() == 1; }
    // A buffer of this list's own with room for `faces` faces and `indices` indices, holding
    // what the list holds (one block: the count and the ints, uninitialised past them).
    void regrow(size_t faces, size_t indices) {
        std::shared_ptr<int[]> grown = std::make_shared_for_overwrite<int[]>(kHeader + faces + 1 + indices);
        int* header = grown.get();
        int* indicesAt = header + kHeader + faces + 1;
        const size_t count = size(), indexTotal = indexCount();
        header[kFaces] = int(count);
        header[kIndexCount] = int(indexTotal);
        header[kFaceRoom] = int(faces);
        header[kIndexRoom] = int(indices);
        header[kHeader] = 0;
        if (count > 0) {
            std::copy_n(buffer_.get() + kHeader, count + 1, header + kHeader);
            std::copy_n(indices_, indexTotal, indicesAt);
        }
        buffer_ = std::move(grown);
        indices_ = indicesAt;
    }

    std::shared_ptr<int[]> buffer_; // none when nothing was ever added
    int* indices_ = nullptr;        // into buffer_, after the starts' room
};

} // namespace shatter::geometry
