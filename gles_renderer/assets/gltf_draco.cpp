#include "gles_renderer/assets/gltf_draco.h"

#include <cmath>
#include <cstring>
#include <limits>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "core/error.h"
#include "gles_renderer/assets/gltf_accessors.h"
#include "gles_renderer/assets/gltf_compression.h"

#if LUMAR_HAVE_DRACO
#include <draco/compression/decode.h>
#include <draco/core/draco_types.h>
#include <draco/mesh/mesh.h>
#endif

namespace lumar::gltf {

#if LUMAR_HAVE_DRACO

namespace {

// One decoded Draco buffer view; several primitives may share it.
struct DecodedGeometry {
    std::unique_ptr<draco::PointCloud> geometry;
    const draco::Mesh* mesh = nullptr; // geometry as a mesh, null for a point cloud
};

DecodedGeometry decodeView(const tinygltf::Model& model, size_t viewIndex, const std::string& what)
{
    const std::string viewName = "bufferView " + std::to_string(viewIndex);
    if (viewIndex >= model.bufferViews.size()) {
        throw InputError(what + ": " + viewName + " does not exist");
    }
    const tinygltf::BufferView& view = model.bufferViews[viewIndex];
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
    draco::DecoderBuffer buffer;
    buffer.Init(reinterpret_cast<const char*>(data.data() + view.byteOffset), view.byteLength);
    const std::string corrupt = what + ": the Draco data in " + viewName + " (" + std::to_string(view.byteLength) +
                                " bytes) is truncated or corrupt";
    auto type = draco::Decoder::GetEncodedGeometryType(&buffer);
    if (!type.ok()) {
        throw InputError(corrupt);
    }
    draco::Decoder decoder;
    DecodedGeometry decoded;
    if (type.value() == draco::TRIANGULAR_MESH) {
        auto mesh = decoder.DecodeMeshFromBuffer(&buffer);
        if (!mesh.ok() || !mesh.value()) {
            throw InputError(corrupt);
        }
        decoded.mesh = mesh.value().get();
        decoded.geometry = std::move(mesh).value();
    } else if (type.value() == draco::POINT_CLOUD) {
        auto cloud = decoder.DecodePointCloudFromBuffer(&buffer);
        if (!cloud.ok() || !cloud.value()) {
            throw InputError(corrupt);
        }
        decoded.geometry = std::move(cloud).value();
    } else {
        throw InputError(corrupt);
    }
    return decoded;
}

// Room for `bytes` more decoded bytes in the model's budget, taken.
void takeBudget(size_t bytes, size_t& bytesLeft, const std::string& what)
{
    if (bytes > bytesLeft) {
        throw InputError(what + ": the decoded data would exceed " + std::to_string(kMaxDecodedBytes) +
                         " bytes in all");
    }
    bytesLeft -= bytes;
}

// Appends `bytes` as a new buffer with one buffer view, and an accessor like `like` reading
// it from the start; returns the accessor's index.
int appendAccessor(tinygltf::Model& model, tinygltf::Accessor like, std::vector<unsigned char> bytes)
{
    tinygltf::BufferView view;
    view.buffer = int(model.buffers.size());
    view.byteLength = bytes.size();
    tinygltf::Buffer buffer;
    buffer.data = std::move(bytes);
    model.buffers.push_back(std::move(buffer));
    like.bufferView = int(model.bufferViews.size());
    model.bufferViews.push_back(view);
    like.byteOffset = 0;
    like.sparse = {};
    model.accessors.push_back(std::move(like));
    return int(model.accessors.size() - 1);
}

double loadDracoComponent(const uint8_t* p, draco::DataType type)
{
    switch (type) {
    case draco::DT_INT8: {
        int8_t v;
        std::memcpy(&v, p, 1);
        return v;
    }
    case draco::DT_UINT8:
    case draco::DT_BOOL:
        return p[0];
    case draco::DT_INT16: {
        int16_t v;
        std::memcpy(&v, p, 2);
        return v;
    }
    case draco::DT_UINT16: {
        uint16_t v;
        std::memcpy(&v, p, 2);
        return v;
    }
    case draco::DT_INT32: {
        int32_t v;
        std::memcpy(&v, p, 4);
        return v;
    }
    case draco::DT_UINT32: {
        uint32_t v;
        std::memcpy(&v, p, 4);
        return v;
    }
    case draco::DT_FLOAT32: {
        float v;
        std::memcpy(&v, p, 4);
        return v;
    }
    default: { // DT_FLOAT64; the other types are refused before
        double v;
        std::memcpy(&v, p, 8);
        return v;
    }
    }
}

// The largest value of an integer Draco type, for normalised attributes read as floats.
double dracoTypeMax(draco::DataType type)
{
    switch (type) {
    case draco::DT_INT8:
        return 127.0;
    case draco::DT_UINT8:
        return 255.0;
    case draco::DT_INT16:
        return 32767.0;
    case draco::DT_UINT16:
        return 65535.0;
    case draco::DT_INT32:
        return 2147483647.0;
    case draco::DT_UINT32:
        return 4294967295.0;
    default:
        return 1.0;
    }
}

// Stores `value` as one component of glTF type `componentType`; false when it does not fit.
bool storeComponent(unsigned char* out, int componentType, double value)
{
    const auto store = [&](auto typed, double lo, double hi) {
        if (!(value >= lo && value <= hi) || value != std::floor(value)) {
            return false;
        }
        typed = static_cast<decltype(typed)>(value);
        std::memcpy(out, &typed, sizeof(typed));
        return true;
    };
    switch (componentType) {
    case TINYGLTF_COMPONENT_TYPE_BYTE:
        return store(int8_t(0), -128.0, 127.0);
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE:
        return store(uint8_t(0), 0.0, 255.0);
    case TINYGLTF_COMPONENT_TYPE_SHORT:
        return store(int16_t(0), -32768.0, 32767.0);
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT:
        return store(uint16_t(0), 0.0, 65535.0);
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT:
        return store(uint32_t(0), 0.0, 4294967295.0);
    default: { // FLOAT
        if (!(std::abs(value) <= double(std::numeric_limits<float>::max()))) {
            return false;
        }
        const float v = float(value);
        std::memcpy(out, &v, 4);
        return true;
    }
    }
}

// The attribute's values for every point, laid out as `accessor` describes them (its type
// and component type; the Draco attribute's own values converted, integers exactly).
std::vector<unsigned char> attributeBytes(const draco::PointAttribute& attribute, const tinygltf::Accessor& accessor,
                                          size_t& bytesLeft, const std::string& what)
{
    const int components = tinygltf::GetNumComponentsInType(uint32_t(accessor.type));
    const int componentBytes = tinygltf::GetComponentSizeInBytes(uint32_t(accessor.componentType));
    if (components <= 0 || componentBytes <= 0 || accessor.componentType == TINYGLTF_COMPONENT_TYPE_DOUBLE ||
        accessor.componentType == TINYGLTF_COMPONENT_TYPE_INT) {
        throw InputError(what + ": the accessor's type or componentType is not a glTF 2.0 one");
    }
    const draco::DataType type = attribute.data_type();
    if (type == draco::DT_INVALID || type == draco::DT_INT64 || type == draco::DT_UINT64 ||
        type >= draco::DT_TYPES_COUNT) {
        throw InputError(what + ": the Draco attribute's data type " + std::to_string(int(type)) +
                         " has no glTF equivalent");
    }
    const bool floatOut = accessor.componentType == TINYGLTF_COMPONENT_TYPE_FLOAT;
    const bool floatIn = type == draco::DT_FLOAT32 || type == draco::DT_FLOAT64;
    if (floatIn && !floatOut) {
        throw InputError(what + ": the Draco attribute holds floats, the accessor integers");
    }
    // Integers into floats as the Draco attribute says (normalised or not); integers into
    // integers unchanged (the accessor's own normalized flag applies when it is read).
    const double scale = floatOut && !floatIn && attribute.normalized() ? 1.0 / dracoTypeMax(type) : 1.0;
    const size_t inComponentBytes = size_t(draco::DataTypeLength(type));
    const size_t inComponents = attribute.num_components();
    const draco::DataBuffer* buffer = attribute.buffer();
    if (buffer == nullptr || attribute.byte_stride() < 0 || attribute.byte_offset() < 0) {
        throw InputError(what + ": the Draco attribute has no data");
    }
    const size_t stride = size_t(attribute.byte_stride());
    const size_t offset = size_t(attribute.byte_offset());
    if (!attribute.is_mapping_identity() && attribute.indices_map_size() < accessor.count) {
        throw InputError(what + ": the Draco attribute maps fewer points than the accessor's count");
    }
    const size_t elementBytes = size_t(components) * size_t(componentBytes);
    takeBudget(accessor.count * elementBytes, bytesLeft, what);
    std::vector<unsigned char> out(accessor.count * elementBytes, 0);
    const size_t inBytes = inComponents * inComponentBytes;
    for (size_t point = 0; point < accessor.count; ++point) {
        const draco::AttributeValueIndex valueIndex = attribute.mapped_index(draco::PointIndex(uint32_t(point)));
        const size_t value = valueIndex.value();
        // Every read below stays inside the attribute's buffer, whatever the file claims.
        const size_t size = buffer->data_size();
        if (value >= attribute.size() || offset > size || inBytes > size - offset ||
            (stride != 0 && value > (size - offset - inBytes) / stride)) {
            throw InputError(what + ": Draco point " + std::to_string(point) + " has no value");
        }
        const uint8_t* in = buffer->data() + offset + value * stride;
        for (size_t c = 0; c < size_t(components); ++c) {
            // Components the attribute lacks stay zero (as Draco's own conversion does).
            const double v = c < inComponents ? loadDracoComponent(in + c * inComponentBytes, type) * scale : 0.0;
            if (!storeComponent(out.data() + point * elementBytes + c * size_t(componentBytes), accessor.componentType,
                                v)) {
                throw InputError(what + ": Draco value " + std::to_string(v) +
                                 " does not fit the accessor's componentType " +
                                 std::to_string(accessor.componentType));
            }
        }
    }
    return out;
}

class DracoPrimitiveDecoder {
public:
    DracoPrimitiveDecoder(tinygltf::Model& model, size_t& bytesLeft) : model_(model), bytesLeft_(bytesLeft) {}

    void decode(size_t meshIndex, size_t primitiveIndex)
    {
        const std::string what =
            "mesh " + std::to_string(meshIndex) + " primitive " + std::to_string(primitiveIndex) + " (" + kDraco + ")";
        tinygltf::Primitive& primitive = model_.meshes[meshIndex].primitives[primitiveIndex];
        const tinygltf::Value extension = primitive.extensions.at(kDraco);
        if (!extension.IsObject()) {
            throw InputError(what + ": the extension is not an object with bufferView and attributes");
        }
        const std::optional<size_t> viewIndex = countMember(extension, "bufferView", what);
        if (!viewIndex) {
            throw InputError(what + ": bufferView is missing");
        }
        const DecodedGeometry& decoded = geometry(*viewIndex, what);
        const size_t points = decoded.geometry->num_points();

        const tinygltf::Value& ids = extension.Get("attributes");
        if (!ids.IsObject()) {
            throw InputError(what + ": attributes is missing or not an object");
        }
        for (auto& [name, accessorIndex] : primitive.attributes) {
            if (!ids.Has(name)) {
                continue; // not compressed: read from its own bufferView
            }
            const std::string attributeWhat = what + " " + name.substr(0, 40);
            const std::optional<size_t> id = countMember(ids, name.c_str(), attributeWhat);
            const draco::PointAttribute* attribute = *id <= std::numeric_limits<uint32_t>::max()
                                                         ? decoded.geometry->GetAttributeByUniqueId(uint32_t(*id))
                                                         : nullptr;
            if (attribute == nullptr) {
                throw InputError(attributeWhat + ": Draco attribute id " + std::to_string(*id) + " does not exist");
            }
            const tinygltf::Accessor& accessor = checkedAccessor(accessorIndex, attributeWhat);
            if (accessor.count != points) {
                throw InputError(attributeWhat + ": accessor " + std::to_string(accessorIndex) + " has count " +
                                 std::to_string(accessor.count) + ", the Draco data " + std::to_string(points) +
                                 " points");
            }
            std::vector<unsigned char> bytes = attributeBytes(*attribute, accessor, bytesLeft_, attributeWhat);
            accessorIndex = appendAccessor(model_, accessor, std::move(bytes));
        }

        std::optional<size_t> indices = countMember(extension, kDracoIndicesKey, what);
        if (!indices && primitive.indices >= 0) {
            indices = size_t(primitive.indices); // a JSON rewrite that did not happen (no "indices" then)
        }
        if (indices) {
            if (decoded.mesh == nullptr) {
                throw InputError(what + ": has indices, but the Draco data is a point cloud");
            }
            const tinygltf::Accessor& accessor = checkedAccessor(*indices, what + " indices");
            const size_t count = size_t(decoded.mesh->num_faces()) * 3;
            if (accessor.count != count) {
                throw InputError(what + ": index accessor " + std::to_string(*indices) + " has count " +
                                 std::to_string(accessor.count) + ", the Draco mesh " + std::to_string(count) +
                                 " indices");
            }
            takeBudget(count * 4, bytesLeft_, what);
            std::vector<unsigned char> bytes(count * 4);
            for (uint32_t f = 0; f < decoded.mesh->num_faces(); ++f) {
                const draco::Mesh::Face& face = decoded.mesh->face(draco::FaceIndex(f));
                for (size_t corner = 0; corner < 3; ++corner) {
                    const uint32_t index = face[corner].value();
                    if (index >= points) {
                        throw InputError(what + ": Draco face " + std::to_string(f) + " refers to point " +
                                         std::to_string(index) + " of " + std::to_string(points));
                    }
                    std::memcpy(bytes.data() + (size_t(f) * 3 + corner) * 4, &index, 4);
                }
            }
            tinygltf::Accessor like = accessor;
            like.componentType = TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT; // the decoded indices' type
            like.normalized = false;
            model_.meshes[meshIndex].primitives[primitiveIndex].indices =
                appendAccessor(model_, like, std::move(bytes));
        }
        model_.meshes[meshIndex].primitives[primitiveIndex].extensions.erase(kDraco);
    }

private:
    const DecodedGeometry& geometry(size_t viewIndex, const std::string& what)
    {
        auto cached = decoded_.find(viewIndex);
        if (cached == decoded_.end()) {
            cached = decoded_.emplace(viewIndex, decodeView(model_, viewIndex, what)).first;
        }
        return cached->second;
    }

    const tinygltf::Accessor& checkedAccessor(size_t index, const std::string& what) const
    {
        if (index >= model_.accessors.size()) {
            throw InputError(what + ": accessor " + std::to_string(index) + " does not exist");
        }
        const tinygltf::Accessor& accessor = model_.accessors[index];
        if (accessor.count > kMaxAccessorElements) {
            throw InputError(what + ": accessor " + std::to_string(index) + " count " + std::to_string(accessor.count) +
                             " exceeds the limit of " + std::to_string(kMaxAccessorElements));
        }
        return accessor;
    }

    tinygltf::Model& model_;
    size_t& bytesLeft_;
    std::map<size_t, DecodedGeometry> decoded_;
};

} // namespace

bool dracoDecoderBuilt()
{
    return true;
}

void decodeDracoPrimitives(tinygltf::Model& model, size_t& bytesLeft)
{
    DracoPrimitiveDecoder decoder(model, bytesLeft);
    for (size_t m = 0; m < model.meshes.size(); ++m) {
        for (size_t p = 0; p < model.meshes[m].primitives.size(); ++p) {
            if (model.meshes[m].primitives[p].extensions.count(kDraco) != 0) {
                decoder.decode(m, p);
            }
        }
    }
}

#else // built without Draco: files that only use the extension read their uncompressed accessors

bool dracoDecoderBuilt()
{
    return false;
}

void decodeDracoPrimitives(tinygltf::Model&, size_t&) {}

#endif

} // namespace lumar::gltf
