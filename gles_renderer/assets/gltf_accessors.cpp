#include "gles_renderer/assets/gltf_accessors.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <string>

#include "core/error.h"

namespace lumar::gltf {
namespace {

size_t componentBytes(int componentType)
{
    switch (componentType) {
    case TINYGLTF_COMPONENT_TYPE_BYTE:
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE:
        return 1;
    case TINYGLTF_COMPONENT_TYPE_SHORT:
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT:
        return 2;
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT:
    case TINYGLTF_COMPONENT_TYPE_FLOAT:
        return 4;
    default:
        return 0; // not a glTF 2.0 accessor component type
    }
}

int typeComponents(int type)
{
    switch (type) {
    case TINYGLTF_TYPE_SCALAR:
        return 1;
    case TINYGLTF_TYPE_VEC2:
        return 2;
    case TINYGLTF_TYPE_VEC3:
        return 3;
    case TINYGLTF_TYPE_VEC4:
        return 4;
    case TINYGLTF_TYPE_MAT2:
        return 4;
    case TINYGLTF_TYPE_MAT3:
        return 9;
    case TINYGLTF_TYPE_MAT4:
        return 16;
    default:
        return 0;
    }
}

// One component at `p` (any alignment) as a double, which holds every glTF integer exactly.
// Normalisation follows the glTF 2.0 specification (§3.11: signed values clamp at -1).
double loadComponent(const unsigned char* p, int componentType, bool normalized)
{
    switch (componentType) {
    case TINYGLTF_COMPONENT_TYPE_BYTE: {
        int8_t v;
        std::memcpy(&v, p, 1);
        return normalized ? std::max(v / 127.0, -1.0) : double(v);
    }
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE:
        return normalized ? p[0] / 255.0 : double(p[0]);
    case TINYGLTF_COMPONENT_TYPE_SHORT: {
        int16_t v;
        std::memcpy(&v, p, 2);
        return normalized ? std::max(v / 32767.0, -1.0) : double(v);
    }
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT: {
        uint16_t v;
        std::memcpy(&v, p, 2);
        return normalized ? v / 65535.0 : double(v);
    }
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT: {
        uint32_t v;
        std::memcpy(&v, p, 4);
        return double(v);
    }
    default: { // FLOAT, the only other type componentBytes() lets through
        float v;
        std::memcpy(&v, p, 4);
        return double(v);
    }
    }
}

// Where `count` elements of `elementBytes` bytes start inside a buffer view, and how far
// apart they are.
struct ElementRange {
    const unsigned char* first = nullptr;
    size_t stride = 0;
};

ElementRange locateElements(const tinygltf::Model& model, int viewIndex, size_t byteOffset, size_t count,
                            size_t elementBytes, bool honourByteStride, const std::string& what)
{
    if (viewIndex < 0 || size_t(viewIndex) >= model.bufferViews.size()) {
        throw InputError(what + ": bufferView " + std::to_string(viewIndex) + " does not exist");
    }
    const tinygltf::BufferView& view = model.bufferViews[size_t(viewIndex)];
    const std::string viewName = "bufferView " + std::to_string(viewIndex);
    if (view.buffer < 0 || size_t(view.buffer) >= model.buffers.size()) {
        throw InputError(what + ": " + viewName + " refers to buffer " + std::to_string(view.buffer) +
                         ", which does not exist");
    }
    const std::vector<unsigned char>& data = model.buffers[size_t(view.buffer)].data;
    if (view.byteOffset > data.size() || view.byteLength > data.size() - view.byteOffset) {
        throw InputError(what + ": " + viewName + " (offset " + std::to_string(view.byteOffset) + ", length " +
                         std::to_string(view.byteLength) + ") lies outside its buffer of " +
                         std::to_string(data.size()) + " bytes");
    }
    const size_t stride = honourByteStride && view.byteStride != 0 ? view.byteStride : elementBytes;
    if (stride < elementBytes) {
        throw InputError(what + ": " + viewName + " byteStride " + std::to_string(stride) +
                         " is smaller than one element (" + std::to_string(elementBytes) + " bytes)");
    }
    ElementRange range;
    range.stride = stride;
    if (count == 0) {
        return range;
    }
    // The last element must end inside the view: offset + (count-1)*stride + elementBytes,
    // evaluated without overflow.
    const bool firstFits = byteOffset <= view.byteLength && elementBytes <= view.byteLength - byteOffset;
    if (!firstFits || (count - 1) > (view.byteLength - byteOffset - elementBytes) / stride) {
        throw InputError(what + ": " + std::to_string(count) + " elements from offset " + std::to_string(byteOffset) +
                         " run past the end of " + viewName + " (" + std::to_string(view.byteLength) + " bytes)");
    }
    range.first = data.data() + view.byteOffset + byteOffset;
    return range;
}

// All components of the accessor as T, `components` per element, sparse values applied.
template <typename T>
std::vector<T> decodeAccessor(const tinygltf::Model& model, const tinygltf::Accessor& accessor, int components,
                              const std::string& what)
{
    const size_t bytesPerComponent = componentBytes(accessor.componentType);
    const size_t elementBytes = bytesPerComponent * size_t(components);
    if (accessor.bufferView < 0) {
        // Zeros plus sparse values: a few hundred bytes of JSON could otherwise claim millions
        // of elements built from nothing (issue 16). No accessor describes more data than the
        // file's buffers hold.
        size_t bufferBytes = 0;
        for (const tinygltf::Buffer& buffer : model.buffers) {
            bufferBytes += buffer.data.size();
        }
        if (accessor.count * elementBytes > bufferBytes) {
            throw InputError(what + ": count " + std::to_string(accessor.count) + " without a bufferView describes " +
                             std::to_string(accessor.count * elementBytes) +
                             " bytes, more than the file's buffers hold (" + std::to_string(bufferBytes) + ")");
        }
    }
    std::vector<T> out(accessor.count * size_t(components), T(0));

    // An accessor without a bufferView reads as zeros (sparse values may then replace some).
    if (accessor.bufferView >= 0) {
        const ElementRange range =
            locateElements(model, accessor.bufferView, accessor.byteOffset, accessor.count, elementBytes, true, what);
        for (size_t i = 0; i < accessor.count; ++i) {
            const unsigned char* element = range.first + i * range.stride;
            for (int c = 0; c < components; ++c) {
                out[i * size_t(components) + size_t(c)] = static_cast<T>(loadComponent(
                    element + size_t(c) * bytesPerComponent, accessor.componentType, accessor.normalized));
            }
        }
    } else if (!accessor.sparse.isSparse) {
        throw InputError(what + ": has neither a bufferView nor sparse values");
    }

    if (!accessor.sparse.isSparse) {
        return out;
    }
    const auto& sparse = accessor.sparse;
    const std::string sparseWhat = what + " sparse";
    if (sparse.count < 1 || size_t(sparse.count) > accessor.count) {
        throw InputError(sparseWhat + ": count " + std::to_string(sparse.count) + " is not within 1.." +
                         std::to_string(accessor.count));
    }
    const int indexType = sparse.indices.componentType;
    if (indexType != TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE && indexType != TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT &&
        indexType != TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT) {
        throw InputError(sparseWhat + ": indices componentType " + std::to_string(indexType) + " is not unsigned");
    }
    if (sparse.indices.byteOffset < 0 || sparse.values.byteOffset < 0) {
        throw InputError(sparseWhat + ": negative byteOffset");
    }
    const size_t sparseCount = size_t(sparse.count);
    // Sparse index and value views are tightly packed (the specification forbids byteStride).
    const ElementRange indices = locateElements(model, sparse.indices.bufferView, size_t(sparse.indices.byteOffset),
                                                sparseCount, componentBytes(indexType), false, sparseWhat + " indices");
    const ElementRange values = locateElements(model, sparse.values.bufferView, size_t(sparse.values.byteOffset),
                                               sparseCount, elementBytes, false, sparseWhat + " values");
    for (size_t s = 0; s < sparseCount; ++s) {
        const double target = loadComponent(indices.first + s * indices.stride, indexType, false);
        if (target >= double(accessor.count)) {
            throw InputError(sparseWhat + ": index " + std::to_string(uint64_t(target)) + " is not below count " +
                             std::to_string(accessor.count));
        }
        const size_t element = size_t(target);
        for (int c = 0; c < components; ++c) {
            out[element * size_t(components) + size_t(c)] =
                static_cast<T>(loadComponent(values.first + s * values.stride + size_t(c) * bytesPerComponent,
                                             accessor.componentType, accessor.normalized));
        }
    }
    return out;
}

// Checks shared by both readers; returns the accessor.
const tinygltf::Accessor& checkedAccessor(const tinygltf::Model& model, int accessorIndex, int components,
                                          const std::string& what)
{
    if (accessorIndex < 0 || size_t(accessorIndex) >= model.accessors.size()) {
        throw InputError(what + " does not exist");
    }
    const tinygltf::Accessor& accessor = model.accessors[size_t(accessorIndex)];
    if (typeComponents(accessor.type) != components) {
        throw InputError(what + ": type has " + std::to_string(typeComponents(accessor.type)) +
                         " components, expected " + std::to_string(components));
    }
    if (componentBytes(accessor.componentType) == 0) {
        throw InputError(what + ": invalid componentType " + std::to_string(accessor.componentType));
    }
    if (accessor.count > kMaxAccessorElements) {
        throw InputError(what + ": count " + std::to_string(accessor.count) + " exceeds the limit of " +
                         std::to_string(kMaxAccessorElements));
    }
    return accessor;
}

} // namespace

std::vector<float> readFloatAccessor(const tinygltf::Model& model, int accessorIndex, int components,
                                     bool allowNormalizedIntegers)
{
    const std::string what = "accessor " + std::to_string(accessorIndex);
    const tinygltf::Accessor& accessor = checkedAccessor(model, accessorIndex, components, what);
    const int type = accessor.componentType;
    const bool quantised =
        (type == TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE || type == TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT) &&
        accessor.normalized;
    if (type != TINYGLTF_COMPONENT_TYPE_FLOAT && !(allowNormalizedIntegers && quantised)) {
        throw InputError(what + ": componentType " + std::to_string(type) + " is not allowed here (" +
                         (allowNormalizedIntegers ? "float or normalized unsigned byte/short" : "float") +
                         " expected)");
    }
    std::vector<float> values = decodeAccessor<float>(model, accessor, components, what);
    if (!std::all_of(values.begin(), values.end(), [](float v) { return std::isfinite(v); })) {
        throw InputError(what + ": holds a non-finite value");
    }
    return values;
}

std::vector<float> readQuantizedAccessor(const tinygltf::Model& model, int accessorIndex, int components)
{
    const std::string what = "accessor " + std::to_string(accessorIndex);
    const tinygltf::Accessor& accessor = checkedAccessor(model, accessorIndex, components, what);
    if (accessor.componentType == TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT) {
        throw InputError(what + ": componentType 5125 (unsigned int) is not allowed here (float, or byte/short as "
                                "KHR_mesh_quantization allows, expected)");
    }
    std::vector<float> values = decodeAccessor<float>(model, accessor, components, what);
    if (!std::all_of(values.begin(), values.end(), [](float v) { return std::isfinite(v); })) {
        throw InputError(what + ": holds a non-finite value");
    }
    return values;
}

int accessorComponents(const tinygltf::Model& model, int accessorIndex)
{
    if (accessorIndex < 0 || size_t(accessorIndex) >= model.accessors.size()) {
        return 0;
    }
    return typeComponents(model.accessors[size_t(accessorIndex)].type);
}

std::vector<uint32_t> readIndexAccessor(const tinygltf::Model& model, int accessorIndex)
{
    const std::string what = "index accessor " + std::to_string(accessorIndex);
    const tinygltf::Accessor& accessor = checkedAccessor(model, accessorIndex, 1, what);
    const int type = accessor.componentType;
    if (type != TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE && type != TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT &&
        type != TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT) {
        throw InputError(what + ": componentType " + std::to_string(type) + " is not an unsigned integer type");
    }
    if (accessor.normalized) {
        throw InputError(what + ": indices must not be normalized");
    }
    return decodeAccessor<uint32_t>(model, accessor, 1, what);
}

std::vector<float> readAccessorAsFloats(const tinygltf::Model& model, int accessorIndex, int components)
{
    const std::string what = "accessor " + std::to_string(accessorIndex);
    const tinygltf::Accessor& accessor = checkedAccessor(model, accessorIndex, components, what);
    std::vector<float> values = decodeAccessor<float>(model, accessor, components, what);
    if (!std::all_of(values.begin(), values.end(), [](float v) { return std::isfinite(v); }))
        throw InputError(what + ": holds a non-finite value");
    return values;
}

} // namespace lumar::gltf
