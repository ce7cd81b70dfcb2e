// The image module (libhairtrace_image.so): host/core/image_files.h's calls on OpenImageIO.  The
// only code that links OpenImageIO; it decides nothing about what goes into a file.
#include "core/image_files.h"

#include <OpenImageIO/filesystem.h>
#include <OpenImageIO/imagebuf.h>
#include <OpenImageIO/imagebufalgo.h>
#include <OpenImageIO/imageio.h>

namespace ht {

namespace {

using namespace OIIO;

ImageSpec to_oiio(const ImageFileSpec& in) {
    ImageSpec spec(in.width, in.height, in.channels, in.bytes ? TypeDesc::UINT8 : TypeDesc::FLOAT);
    if (!in.channel_names.empty()) spec.channelnames = in.channel_names;
    spec.alpha_channel = in.alpha_channel;
    spec.z_channel = in.z_channel;
    for (const auto& [k, v] : in.attributes.text) spec.attribute(k, v);
    for (const auto& [k, v] : in.attributes.ints) spec.attribute(k, v);
    for (const auto& [k, v] : in.attributes.floats) spec.attribute(k, v);
    return spec;
}

ImageFileSpec from_oiio(const ImageSpec& spec, bool bytes) {
    ImageFileSpec out;
    out.width = spec.width;
    out.height = spec.height;
    out.channels = spec.nchannels;
    out.bytes = bytes;
    out.channel_names = spec.channelnames;
    out.alpha_channel = spec.alpha_channel;
    out.z_channel = spec.z_channel;
    for (const ParamValue& p : spec.extra_attribs) {
        const TypeDesc t = p.type();
        if (p.nvalues() != 1 || t.aggregate != TypeDesc::SCALAR || t.arraylen != 0) continue;
        if (t.basetype == TypeDesc::STRING)
            out.attributes.text.emplace_back(p.name().string(), p.get_string());
        else if (t.basetype == TypeDesc::FLOAT || t.basetype == TypeDesc::DOUBLE || t.basetype == TypeDesc::HALF)
            out.attributes.floats.emplace_back(p.name().string(), p.get_float());
        else if (t.basetype >= TypeDesc::UINT8 && t.basetype <= TypeDesc::INT64)
            out.attributes.ints.emplace_back(p.name().string(), p.get_int());
    }
    return out;
}

ImageFileResult fail(ImageFileStatus status, std::string error) { return {status, std::move(error)}; }

ImageFileResult write(const std::string& format_path, const std::string& file, const ImageFileSpec& spec,
                      const void* pixels) {
    auto out = ImageOutput::create(format_path);
    if (!out) return fail(ImageFileStatus::NoFormat, OIIO::geterror());
    if (!out->open(file, to_oiio(spec))) return fail(ImageFileStatus::OpenFailed, out->geterror());
    bool ok = out->write_image(spec.bytes ? TypeDesc::UINT8 : TypeDesc::FLOAT, pixels);
    std::string err = out->geterror();
    ok = out->close() && ok;
    if (ok) return {};
    if (err.empty()) err = out->geterror();
    return fail(ImageFileStatus::IoFailed, err);
}

ImageFileResult read(const std::string& path, const std::function<bool(const ImageFileSpec&)>& accept,
                     ImageFileSpec* spec, std::vector<float>* pixels) {
    auto in = ImageInput::open(path);
    if (!in) return fail(ImageFileStatus::OpenFailed, OIIO::geterror());
    const ImageSpec& s = in->spec();
    *spec = from_oiio(s, false);
    if (accept && !accept(*spec)) return {};
    pixels->assign(size_t(s.width) * size_t(s.height) * size_t(s.nchannels), 0.0f);
    if (!in->read_image(0, 0, 0, s.nchannels, TypeDesc::FLOAT, pixels->data()))
        return fail(ImageFileStatus::IoFailed, in->geterror());
    in->close();
    return {};
}

ImageFileResult decode(const unsigned char* bytes, size_t size, const char* format_name,
                       const std::function<bool(const ImageFileSpec&)>& accept, ImageFileSpec* spec,
                       std::vector<unsigned char>* pixels) {
    // OIIO reads through the proxy, never from the disk, and only with the plugin named here:
    // no other of OIIO's many readers ever sees the bytes.
    Filesystem::IOMemReader proxy(bytes, size);
    auto in = ImageInput::create(format_name, false, nullptr, &proxy);
    ImageSpec config, opened;
    void* proxy_ptr = &proxy;
    config.attribute("oiio:ioproxy", TypeDesc::PTR, &proxy_ptr);
    // The PNG reader premultiplies colour by alpha unless told not to; alpha is not coverage here.
    config.attribute("oiio:UnassociatedAlpha", 1);
    if (!in || !in->open("texture", opened, config))
        return fail(ImageFileStatus::OpenFailed, in ? in->geterror() : OIIO::geterror());
    const ImageSpec& s = in->spec();
    *spec = from_oiio(s, true);
    if (s.depth != 1) spec->width = spec->height = 0;  // volumes have no place here
    if (!accept(*spec)) return {};
    pixels->assign(size_t(s.width) * size_t(s.height) * size_t(s.nchannels), 0);
    if (!in->read_image(0, 0, 0, s.nchannels, TypeDesc::UINT8, pixels->data()))
        return fail(ImageFileStatus::IoFailed, in->geterror());
    in->close();
    return {};
}

void render_text(std::vector<float>& rgb, int width, int height, const std::vector<ImageTextLabel>& labels,
                 const std::string& font) {
    ImageBuf buf(ImageSpec(width, height, 3, TypeDesc::FLOAT), rgb.data());
    ImageBuf img;
    img.copy(buf);
    for (const ImageTextLabel& l : labels)
        if (!l.text.empty()) ImageBufAlgo::render_text(img, l.x, l.y, l.text, l.size, font, {0.f, 0.f, 0.f});
    img.get_pixels(ROI(0, width, 0, height, 0, 1, 0, 3), TypeDesc::FLOAT, rgb.data());
}

std::string global_attribute(const std::string& name) {
    std::string value;
    OIIO::getattribute(name, value);
    return value;
}

const ImageFilesApi kApi = {kImageFilesAbi, write, read, decode, render_text, global_attribute};

}  // namespace

}  // namespace ht

extern "C" __attribute__((visibility("default"))) const ht::ImageFilesApi* ht_image_files_api() { return &ht::kApi; }
