// Image read/write through OpenImageIO: the one C++ file of io/, built as the image module
// (libsquama_image.so) that module.c opens at the first image. Every exception stops at
// the module's table of C functions and becomes an SqStatus.
#include <OpenImageIO/imagebuf.h>
#include <OpenImageIO/imagebufalgo.h>
#include <OpenImageIO/filesystem.h>
#include <OpenImageIO/imageio.h>
#include <OpenImageIO/strutil.h>

#include <algorithm>
#include <atomic>
#include <cctype>
#include <cstdio>
#include <cstring>
#include <mutex>
#include <string>
#include <sys/stat.h>
#include <unistd.h>
#include <vector>

#include "io_internal.h"
#include "squama/io.h"

using namespace OIIO;

namespace {

std::string lower(std::string s)
{
    for (auto &c : s)
        c = (char)std::tolower((unsigned char)c);
    return s;
}

std::string first_line(std::string s)
{
    auto nl = s.find('\n');
    if (nl != std::string::npos)
        s.resize(nl);
    return s.empty() ? std::string("unknown reason") : s;
}

// OpenImageIO 2.4's PNG reader records libpng's error and returns from libpng's error
// handler, so libpng's default handler runs after it and prints the same error on stderr
// ("libpng error: IHDR: CRC error") before the squama error that names the file. While a
// PNG is read, stderr goes to a temporary file; what arrives there is passed on after,
// less those lines. Reads take turns: the redirection is the whole process's.
class LibpngErrorsDropped {
  public:
    LibpngErrorsDropped() : turn_(turns())
    {
        std::fflush(stderr);
        if ((tmp_ = std::tmpfile()) && (saved_ = dup(2)) >= 0 && dup2(fileno(tmp_), 2) < 0) {
            close(saved_);
            saved_ = -1;
        }
    }
    ~LibpngErrorsDropped()
    {
        if (saved_ >= 0) {
            std::fflush(stderr);
            dup2(saved_, 2);
            close(saved_);
            std::rewind(tmp_);
            char line[1024];
            bool start = true; // at the start of a line (fgets splits longer ones)
            while (std::fgets(line, sizeof line, tmp_)) {
                if (!start || std::strncmp(line, "libpng error: ", 14) != 0)
                    std::fputs(line, stderr);
                start = std::strchr(line, '\n') != nullptr;
            }
        }
        if (tmp_)
            std::fclose(tmp_);
    }
    LibpngErrorsDropped(const LibpngErrorsDropped &) = delete;
    LibpngErrorsDropped &operator=(const LibpngErrorsDropped &) = delete;

  private:
    static std::mutex &turns()
    {
        static std::mutex m;
        return m;
    }
    std::lock_guard<std::mutex> turn_;
    FILE *tmp_ = nullptr;
    int saved_ = -1;
};

bool is_png(const char *path)
{
    static const unsigned char sig[8] = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n'};
    unsigned char head[8];
    FILE *f = std::fopen(path, "rb");
    const bool png = f && std::fread(head, 1, 8, f) == 8 && std::memcmp(head, sig, 8) == 0;
    if (f)
        std::fclose(f);
    return png;
}

// A reader's message without the file's name where it quotes it ("... (\"photo.jpg\")"),
// as OpenImageIO's JPEG reader does: the squama error names the file once, at its end.
std::string unquoted(std::string msg, const char *path)
{
    const std::string quoted = std::string(" (\"") + path + "\")";
    for (size_t at = msg.find(quoted); at != std::string::npos; at = msg.find(quoted, at))
        msg.erase(at, quoted.size());
    return msg;
}

SqStatus read_image(const char *path, const SqReadOptions *opt, SqImage *rgba, SqImage *mask,
                    SqError *err)
{
    long long max_pixels = opt && opt->max_pixels > 0 ? opt->max_pixels
                                                      : (long long)SQ_IO_DEFAULT_MAX_PIXELS;
    if (access(path, R_OK) != 0)
        return sq_error_set(err, SQ_ERR_IO, path, "cannot open image: %s", std::strerror(errno));
    struct stat st;
    if (stat(path, &st) == 0 && S_ISDIR(st.st_mode))
        return sq_error_set(err, SQ_ERR_IO, path, "cannot open image: it is a folder");

    ImageSpec config;
    config.attribute("oiio:UnassociatedAlpha", 1); // keep colours as stored beside alpha
    auto in = ImageInput::open(path, &config);
    if (!in)
        return sq_error_set(err, SQ_ERR_PARSE, path, "not a readable image: %s",
                            unquoted(first_line(OIIO::geterror()), path).c_str());
    const ImageSpec &spec = in->spec();
    if (spec.width <= 0 || spec.height <= 0 || spec.depth > 1 || spec.nchannels < 1)
        return sq_error_set(err, SQ_ERR_UNSUPPORTED, path,
                            "unsupported image geometry %dx%dx%d with %d channels", spec.width,
                            spec.height, spec.depth, spec.nchannels);
    long long npix = (long long)spec.width * spec.height;
    if (npix > max_pixels)
        return sq_error_set(err, SQ_ERR_LIMIT, path,
                            "image is %dx%d (%.1f megapixels), over the limit of %.1f megapixels",
                            spec.width, spec.height, npix / 1e6, max_pixels / 1e6);

    const int w = spec.width, h = spec.height, nch = spec.nchannels;
    std::vector<float> buf((size_t)npix * (size_t)nch);
    if (!in->read_image(0, 0, 0, nch, TypeDesc::FLOAT, buf.data()) || in->has_error()) {
        std::string msg = unquoted(first_line(in->geterror()), path);
        return sq_error_set(err, SQ_ERR_PARSE, path, "corrupt or truncated image: %s",
                            msg.c_str());
    }
    int alpha = spec.alpha_channel;
    if (alpha < 0 && (nch == 2 || nch == 4))
        alpha = nch - 1;
    const bool linear = lower(spec.get_string_attribute("oiio:ColorSpace")).find("linear") !=
                        std::string::npos;
    const int orientation = spec.get_int_attribute("Orientation", 1);
    in->close();

    // Expand to RGBA (+ alpha), then let OpenImageIO apply the EXIF orientation.
    ImageSpec ospec(w, h, 4, TypeDesc::FLOAT);
    ospec.attribute("Orientation", orientation);
    ImageBuf src(ospec);
    std::vector<float> px((size_t)npix * 4);
    for (size_t i = 0; i < (size_t)npix; i++) {
        const float *s = &buf[i * (size_t)nch];
        float *d = &px[i * 4];
        int colour = nch >= 3 ? 3 : 1;
        for (int c = 0; c < 3; c++)
            d[c] = colour == 3 ? s[c] : s[0];
        d[3] = alpha >= 0 ? s[alpha] : 1.0f;
    }
    buf.clear();
    buf.shrink_to_fit();
    src.set_pixels(src.roi(), TypeDesc::FLOAT, px.data());
    ImageBuf oriented = ImageBufAlgo::reorient(src);
    if (oriented.has_error())
        return sq_error_set(err, SQ_ERR_INTERNAL, path, "cannot orient image: %s",
                            first_line(oriented.geterror()).c_str());
    const ROI roi = oriented.roi();
    const int ow = roi.width(), oh = roi.height();

    if (sq_image_alloc(rgba, ow, oh, 4, linear ? SQ_SPACE_LINEAR : SQ_SPACE_SRGB) != 0)
        return sq_error_set(err, SQ_ERR_NOMEM, path, "out of memory for a %dx%d image", ow, oh);
    if (!oriented.get_pixels(roi, TypeDesc::FLOAT, rgba->px)) {
        sq_image_free(rgba);
        return sq_error_set(err, SQ_ERR_INTERNAL, path, "cannot copy pixels");
    }
    if (mask) {
        std::memset(mask, 0, sizeof *mask);
        if (alpha >= 0) {
            if (sq_image_alloc(mask, ow, oh, 1, SQ_SPACE_DATA) != 0) {
                sq_image_free(rgba);
                return sq_error_set(err, SQ_ERR_NOMEM, path, "out of memory for a mask");
            }
            for (size_t i = 0; i < (size_t)ow * oh; i++)
                mask->px[i] = rgba->px[i * 4 + 3] >= 0.5f ? 1.0f : 0.0f;
        }
    }
    return SQ_OK;
}

SqImageFormat format_from_name(const char *path)
{
    std::string p = lower(path);
    auto ends = [&](const char *e) {
        size_t n = std::strlen(e);
        return p.size() >= n && p.compare(p.size() - n, n, e) == 0;
    };
    if (ends(".png"))
        return SQ_FORMAT_PNG;
    if (ends(".exr"))
        return SQ_FORMAT_EXR;
    if (ends(".jpg") || ends(".jpeg"))
        return SQ_FORMAT_JPEG;
    return SQ_FORMAT_AUTO;
}

/* the image being written when libjpeg exits the program (sq_io_image_under_way) */
static std::atomic<const char *> under_way{nullptr};

/* 1 when the file at path ends as a whole PNG (its IEND chunk) or JPEG (its EOI marker)
 * does: a write that ran out of disk or hit a file size limit stops short of it, and
 * OIIO 2.4's PNG writer does not report that. */
static bool ends_whole(const char *path, bool jpeg)
{
    static const unsigned char iend[12] = {0, 0, 0, 0, 'I', 'E', 'N', 'D', 0xAE, 0x42, 0x60, 0x82};
    static const unsigned char eoi[2] = {0xFF, 0xD9};
    const unsigned char *want = jpeg ? eoi : iend;
    const long n = jpeg ? 2 : 12;
    unsigned char tail[12];
    FILE *f = std::fopen(path, "rb");
    if (!f)
        return true; /* not readable by its writer (a umask of 0477): not checked, as fsync is not */
    bool ok = std::fseek(f, -n, SEEK_END) == 0 && std::fread(tail, 1, (size_t)n, f) == (size_t)n &&
              std::memcmp(tail, want, (size_t)n) == 0;
    std::fclose(f);
    return ok;
}

SqStatus write_image(const char *path, const SqImage *img, const SqWriteOptions *opt,
                     SqError *err)
{
    SqWriteOptions o = opt ? *opt : SqWriteOptions{SQ_FORMAT_AUTO, 0, 0};
    if (o.format == SQ_FORMAT_AUTO)
        o.format = format_from_name(path);
    if (o.format == SQ_FORMAT_AUTO)
        return sq_error_set(err, SQ_ERR_UNSUPPORTED, path,
                            "cannot tell the image format from the name: use .png, .exr or .jpg");
    if (!img || !img->px || img->width <= 0 || img->height <= 0 || img->channels < 1 ||
        img->channels > 4)
        return sq_error_set(err, SQ_ERR_INVALID, path, "no image to write");
    const bool jpeg = o.format == SQ_FORMAT_JPEG;
    const bool png = o.format == SQ_FORMAT_PNG || jpeg; /* display-referred, clamped */
    if (o.bits == 0)
        o.bits = png ? 8 : 16;
    if (jpeg ? o.bits != 8 : png ? (o.bits != 8 && o.bits != 16) : (o.bits != 16 && o.bits != 32))
        return sq_error_set(err, SQ_ERR_INVALID, path,
                            "%d-bit %s is not supported (PNG: 8 or 16, EXR: 16 or 32, JPEG: 8)",
                            o.bits, jpeg ? "JPEG" : png ? "PNG" : "EXR");
    if (o.quality < 0 || o.quality > 100)
        return sq_error_set(err, SQ_ERR_INVALID, path, "JPEG quality %d is outside 1..100", o.quality);

    const int w = img->width, h = img->height, nch = img->channels;
    const int colour = nch >= 3 ? 3 : (nch == 2 ? 1 : nch); // channels that carry colour
    std::vector<float> px((size_t)w * h * nch);
    for (size_t i = 0; i < px.size(); i++) {
        float v = img->px[i];
        bool is_colour = (int)(i % (size_t)nch) < colour && img->space != SQ_SPACE_DATA;
        if (is_colour && png && img->space == SQ_SPACE_LINEAR)
            v = sq_io_linear_to_srgb(std::max(v, 0.0f));
        else if (is_colour && !png && img->space == SQ_SPACE_SRGB)
            v = sq_io_srgb_to_linear(v);
        if (png)
            v = std::min(1.0f, std::max(0.0f, v)); // NaN becomes 0
        px[i] = v;
    }

    TypeDesc type = png ? (o.bits == 16 ? TypeDesc::UINT16 : TypeDesc::UINT8)
                        : (o.bits == 32 ? TypeDesc::FLOAT : TypeDesc::HALF);
    int out_ch = nch;
    if (jpeg && (nch == 2 || nch == 4)) { /* JPEG has no alpha */
        out_ch = nch - 1;
        std::vector<float> noalpha((size_t)w * h * out_ch);
        for (size_t i = 0; i < (size_t)w * h; i++)
            for (int c = 0; c < out_ch; c++)
                noalpha[i * out_ch + c] = px[i * nch + c];
        px.swap(noalpha);
    }
    ImageSpec spec(w, h, out_ch, type);
    if (jpeg)
        spec.attribute("Compression", Strutil::fmt::format("jpeg:{}", o.quality ? o.quality : 90));
    if (!jpeg && (nch == 2 || nch == 4)) {
        spec.alpha_channel = nch - 1;
        spec.attribute("oiio:UnassociatedAlpha", 1);
    }
    if (img->space != SQ_SPACE_DATA)
        spec.attribute("oiio:ColorSpace", png ? "sRGB" : "Linear");
    if (!png)
        spec.attribute("compression", "zip");

    char tmp[4096];
    if (sq__io_make_temp(path, tmp, sizeof tmp) != 0)
        return sq_error_set(err, SQ_ERR_IO, path, "cannot create a file here: %s",
                            std::strerror(errno));
    auto out = ImageOutput::create(jpeg ? "jpeg" : png ? "png" : "openexr");
    under_way.store(path);
    bool ok = out && out->open(tmp, spec) &&
              out->write_image(TypeDesc::FLOAT, px.data()) && out->close();
    under_way.store(nullptr);
    if (!ok) {
        std::string msg = first_line(out ? out->geterror() : OIIO::geterror());
        /* OpenEXR names the file it was writing: the temporary one, which is gone */
        for (size_t at = msg.find(tmp); at != std::string::npos; at = msg.find(tmp, at + std::strlen(path)))
            msg.replace(at, std::strlen(tmp), path);
        sq__io_drop_temp(tmp);
        return sq_error_set(err, SQ_ERR_IO, path, "cannot write image: %s", msg.c_str());
    }
    if ((png || jpeg) && !ends_whole(tmp, jpeg)) { /* OIIO 2.4's PNG writer reports success */
        sq__io_drop_temp(tmp);
        return sq_error_set(err, SQ_ERR_IO, path, "cannot write image: the file came out cut short (is the disk full?)");
    }
    return sq__io_commit(tmp, path, err);
}

SqStatus read_any(const char *path, const SqReadOptions *opt, SqImage *rgba, SqImage *mask, SqError *err)
{
    std::memset(rgba, 0, sizeof *rgba);
    if (mask)
        std::memset(mask, 0, sizeof *mask);
    try {
        if (is_png(path)) {
            LibpngErrorsDropped quiet;
            return read_image(path, opt, rgba, mask, err);
        }
        return read_image(path, opt, rgba, mask, err);
    } catch (const std::bad_alloc &) {
        sq_image_free(rgba);
        sq_image_free(mask);
        return sq_error_set(err, SQ_ERR_NOMEM, path, "out of memory reading the image");
    } catch (const std::exception &e) {
        sq_image_free(rgba);
        sq_image_free(mask);
        return sq_error_set(err, SQ_ERR_PARSE, path, "cannot read image: %s", e.what());
    } catch (...) {
        sq_image_free(rgba);
        sq_image_free(mask);
        return sq_error_set(err, SQ_ERR_INTERNAL, path, "cannot read image");
    }
}

// DejaVu Sans, found once. Named without its path, OpenImageIO 2.4 looks for a font through
// the font folders on every call (most of a labelled picture's time); a path is opened as
// it is. Where the system's folders do not have it, its name: OpenImageIO's own search.
const std::string &label_font()
{
    static const std::string font = [] {
        const std::vector<std::string> dirs = {"/usr/share/fonts", "/usr/local/share/fonts"};
        std::string path = Filesystem::searchpath_find("DejaVuSans.ttf", dirs, false, true);
        return path.empty() ? std::string("DejaVuSans") : path;
    }();
    return font;
}

SqStatus draw_text(SqImage *img, int x, int y, int px_size, const char *text, const float color[3],
                   SqError *err)
{
    if (!img || !img->px || img->channels < 3 || !text)
        return sq_error_set(err, SQ_ERR_INVALID, "text", "no colour image to draw on");
    if (!text[0])
        return SQ_OK;
    try {
        // The glyphs' coverage is drawn into a buffer of their own that holds the whole
        // text, then blended into the image where the two overlap: OpenImageIO 2.4's
        // render_text aborts (a failed assertion, not an error) on text that runs over
        // the image's edge, as a label beside a point near the top of a photo does.
        ROI box = ImageBufAlgo::text_size(text, px_size, label_font());
        if (!box.defined())
            return sq_error_set(err, SQ_ERR_UNSUPPORTED, "text", "cannot draw text: no DejaVu Sans font found");
        if (box.width() <= 0 || box.height() <= 0) // an empty or inverted box: nothing to draw
            return SQ_OK;
        const int pad = 2, w = box.width() + 2 * pad, h = box.height() + 2 * pad;
        const int x0 = x + box.xbegin - pad, y0 = y + box.ybegin - pad; // the buffer's place in img
        if (x0 >= img->width || y0 >= img->height || x0 + w <= 0 || y0 + h <= 0)
            return SQ_OK; // nothing of it shows
        ImageBuf cover(ImageSpec(w, h, 1, TypeDesc::FLOAT));
        ImageBufAlgo::zero(cover);
        const float one = 1.0f;
        if (!ImageBufAlgo::render_text(cover, x - x0, y - y0, text, px_size, label_font(), cspan<float>(&one, 1)))
            return sq_error_set(err, SQ_ERR_UNSUPPORTED, "text", "cannot draw text: %s", cover.geterror().c_str());
        const float *a = static_cast<const float *>(cover.localpixels());
        const int ch = img->channels;
        for (int j = y0 < 0 ? -y0 : 0; j < h && y0 + j < img->height; j++)
            for (int i = x0 < 0 ? -x0 : 0; i < w && x0 + i < img->width; i++) {
                const float t = a[(size_t)j * w + i];
                if (t <= 0)
                    continue;
                float *px = img->px + ((size_t)(y0 + j) * img->width + (size_t)(x0 + i)) * ch;
                for (int c = 0; c < 3; c++)
                    px[c] = color[c] * t + px[c] * (1 - t);
                if (ch > 3)
                    px[3] = t + px[3] * (1 - t);
            }
        return SQ_OK;
    } catch (const std::exception &e) {
        return sq_error_set(err, SQ_ERR_INTERNAL, "text", "cannot draw text: %s", e.what());
    }
}

const char *image_under_way()
{
    return under_way.load();
}

SqStatus write_any(const char *path, const SqImage *img, const SqWriteOptions *opt, SqError *err)
{
    try {
        return write_image(path, img, opt, err);
    } catch (const std::bad_alloc &) {
        return sq_error_set(err, SQ_ERR_NOMEM, path, "out of memory writing the image");
    } catch (const std::exception &e) {
        return sq_error_set(err, SQ_ERR_IO, path, "cannot write image: %s", e.what());
    } catch (...) {
        return sq_error_set(err, SQ_ERR_INTERNAL, path, "cannot write image");
    }
}

const SqImageModule table = {SQ_IMAGE_MODULE_ABI, read_any, write_any, draw_text, image_under_way};

} // namespace

extern "C" const SqImageModule *sq__image_module(void)
{
    return &table;
}
