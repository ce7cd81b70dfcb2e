#include "scene/gltf_accessor.h"

#include <cstring>

#include "scene/scene_error.h"

namespace ht {

namespace {

// An accessor resolved to raw bytes: element i starts at base + i * stride.
struct ElementRange {
    const unsigned char* base = nullptr;
    size_t stride = 0;
    size_t count = 0;
    int component_type = 0;
};

size_t component_bytes(int component_type) {
    switch (component_type) {
        case TINYGLTF_COMPONENT_TYPE_BYTE:
        case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE: return 1;
        case TINYGLTF_COMPONENT_TYPE_SHORT:
        case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT: return 2;
        case TINYGLTF_COMPONENT_TYPE_INT:
        case TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT:
        case TINYGLTF_COMPONENT_TYPE_FLOAT: return 4;
        case TINYGLTF_COMPONENT_TYPE_DOUBLE: return 8;
        default: return 0;
    }
}

ElementRange resolve(const tinygltf::Model& model, int index, int expected_type,
                     const char* expected_type_name, const std::string& file,
                     const std::string& what) {
    if (index < 0 || static_cast<size_t>(index) >= model.accessors.size())
        scene_fail(file, what, ": accessor ", index, " does not exist");
    const tinygltf::Accessor& acc = model.accessors[index];
    if (acc.sparse.isSparse)
        scene_fail(file, what, ": sparse accessors are not supported (accessor ", index, ")");
    if (acc.type != expected_type)
        scene_fail(file, what, ": accessor ", index, " must be ", expected_type_name);
    const size_t components = expected_type == TINYGLTF_TYPE_VEC3   ? 3
                              : expected_type == TINYGLTF_TYPE_VEC2 ? 2
                                                                    : 1;
    const size_t comp_bytes = component_bytes(acc.componentType);
    if (comp_bytes == 0)
        scene_fail(file, what, ": accessor ", index, " has invalid componentType ",
                   acc.componentType);
    const size_t element_bytes = components * comp_bytes;

    ElementRange range;
    range.component_type = acc.componentType;
    range.count = acc.count;
    if (acc.count == 0) return range;
    if (acc.bufferView < 0 || static_cast<size_t>(acc.bufferView) >= model.bufferViews.size())
        scene_fail(file, what, ": accessor ", index, " has no valid bufferView (",
                   acc.bufferView, ")");
    const tinygltf::BufferView& view = model.bufferViews[acc.bufferView];
    if (view.buffer < 0 || static_cast<size_t>(view.buffer) >= model.buffers.size())
        scene_fail(file, what, ": bufferView ", acc.bufferView, " refers to missing buffer ",
                   view.buffer);
    const tinygltf::Buffer& buffer = model.buffers[view.buffer];
    if (view.byteOffset > buffer.data.size() || view.byteLength > buffer.data.size() - view.byteOffset)
        scene_fail(file, what, ": bufferView ", acc.bufferView, " (bytes ", view.byteOffset,
                   " + ", view.byteLength, ") exceeds buffer ", view.buffer, " (",
                   buffer.data.size(), " bytes)");
    const size_t stride = view.byteStride ? view.byteStride : element_bytes;
    if (stride < element_bytes)
        scene_fail(file, what, ": byteStride ", stride, " is smaller than an element (",
                   element_bytes, " bytes)");
    // Last element must end inside the view: offset + stride*(count-1) + element <= length,
    // written so that no product can overflow.
    const size_t offset = acc.byteOffset;
    if (offset > view.byteLength || element_bytes > view.byteLength - offset ||
        acc.count - 1 > (view.byteLength - offset - element_bytes) / stride)
        scene_fail(file, what, ": accessor ", index, " (", acc.count, " elements from byte ",
                   offset, ", stride ", stride, ") exceeds bufferView ", acc.bufferView, " (",
                   view.byteLength, " bytes)");
    range.base = buffer.data.data() + view.byteOffset + offset;
    range.stride = stride;
    return range;
}

}  // namespace

std::vector<Vec3f> read_float_vec3_accessor(const tinygltf::Model& model, int accessor,
                                            const std::string& file, const std::string& what) {
    const ElementRange r = resolve(model, accessor, TINYGLTF_TYPE_VEC3, "VEC3", file, what);
    if (r.component_type != TINYGLTF_COMPONENT_TYPE_FLOAT)
        scene_fail(file, what, ": accessor ", accessor, " must hold FLOAT components");
    std::vector<Vec3f> out(r.count);
    for (size_t i = 0; i < r.count; ++i) std::memcpy(&out[i], r.base + i * r.stride, sizeof(Vec3f));
    return out;
}

std::vector<float> read_float_scalar_accessor(const tinygltf::Model& model, int accessor,
                                              const std::string& file, const std::string& what) {
    const ElementRange r = resolve(model, accessor, TINYGLTF_TYPE_SCALAR, "SCALAR", file, what);
    if (r.component_type != TINYGLTF_COMPONENT_TYPE_FLOAT)
        scene_fail(file, what, ": accessor ", accessor, " must hold FLOAT components");
    std::vector<float> out(r.count);
    for (size_t i = 0; i < r.count; ++i) std::memcpy(&out[i], r.base + i * r.stride, sizeof(float));
    return out;
}

std::vector<std::array<float, 2>> read_texcoord_accessor(const tinygltf::Model& model, int accessor,
                                                        const std::string& file,
                                                        const std::string& what) {
    const ElementRange r = resolve(model, accessor, TINYGLTF_TYPE_VEC2, "VEC2", file, what);
    const bool normalized = model.accessors[accessor].normalized;
    const bool ok = r.component_type == TINYGLTF_COMPONENT_TYPE_FLOAT ||
                    (normalized && (r.component_type == TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE ||
                                    r.component_type == TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT));
    if (!ok)
        scene_fail(file, what, ": accessor ", accessor,
                   " must hold FLOAT or normalized UNSIGNED_BYTE / UNSIGNED_SHORT components");
    std::vector<std::array<float, 2>> out(r.count);
    for (size_t i = 0; i < r.count; ++i) {
        const unsigned char* p = r.base + i * r.stride;
        for (int c = 0; c < 2; ++c) {
            float v;
            if (r.component_type == TINYGLTF_COMPONENT_TYPE_FLOAT) {
                std::memcpy(&v, p + 4 * c, 4);
            } else if (r.component_type == TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE) {
                v = p[c] / 255.0f;
            } else {
                uint16_t s;
                std::memcpy(&s, p + 2 * c, 2);
                v = s / 65535.0f;
            }
            out[i][c] = v;
        }
    }
    return out;
}

std::vector<uint32_t> read_index_accessor(const tinygltf::Model& model, int accessor,
                                          size_t vertex_count, const std::string& file,
                                          const std::string& what) {
    const ElementRange r = resolve(model, accessor, TINYGLTF_TYPE_SCALAR, "SCALAR", file, what);
    std::vector<uint32_t> out(r.count);
    for (size_t i = 0; i < r.count; ++i) {
        const unsigned char* p = r.base + i * r.stride;
        uint32_t v = 0;
        switch (r.component_type) {
            case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE: v = *p; break;
            case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT: {
                uint16_t s;
                std::memcpy(&s, p, 2);
                v = s;
                break;
            }
            case TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT: std::memcpy(&v, p, 4); break;
            default:
                scene_fail(file, what, ": index accessor ", accessor,
                           " must hold unsigned byte, short or int components");
        }
        if (v >= vertex_count)
            scene_fail(file, what, ": index ", v, " (element ", i, ") is out of range for ",
                       vertex_count, " vertices");
        out[i] = v;
    }
    return out;
}

}  // namespace ht
