// OpenCV behind a C interface for photo preparation. Exceptions stop here.
#include <opencv2/imgproc.hpp>
#include <opencv2/saliency.hpp>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <mutex>
#include <vector>

#include "cv_bridge.h"

extern "C" int sq__cv_resize(const float *src, int sw, int sh, int ch, float *dst, int dw, int dh)
{
    try {
        cv::Mat in(sh, sw, CV_32FC(ch), const_cast<float *>(src));
        cv::Mat out(dh, dw, CV_32FC(ch), dst);
        cv::resize(in, out, cv::Size(dw, dh), 0, 0, dw < sw ? cv::INTER_AREA : cv::INTER_LINEAR);
        return out.data == reinterpret_cast<uchar *>(dst) ? 0 : -1;
    } catch (...) {
        return -1;
    }
}

/* GrabCut's colour models start from k-means, which draws from OpenCV's per-thread
 * generator: seeded before every call, a mask depends on the photo alone, not on what ran
 * on the thread before (a batch's second row, an MPI rank's). */
static const int GRABCUT_SEED = 0x5eed;
static const int BAND_SIDE = 512, BAND_REACH = 16; /* sq__cv_grabcut_band's scale */

extern "C" int sq__cv_grabcut(const float *rgb, int w, int h, double inset, uint8_t *mask)
{
    try {
        cv::Mat f(h, w, CV_32FC3, const_cast<float *>(rgb)), img;
        f.convertTo(img, CV_8UC3, 255.0);
        cv::Mat m(h, w, CV_8UC1), bgd, fgd;
        int dx = (int)(inset * w), dy = (int)(inset * h);
        cv::Rect rect(dx, dy, w - 2 * dx, h - 2 * dy);
        cv::setRNGSeed(GRABCUT_SEED);
        cv::grabCut(img, m, rect, bgd, fgd, 5, cv::GC_INIT_WITH_RECT);
        for (int i = 0; i < w * h; i++)
            mask[i] = (m.data[i] == cv::GC_FGD || m.data[i] == cv::GC_PR_FGD) ? 255 : 0;
        return 0;
    } catch (...) {
        return -1;
    }
}

extern "C" int sq__cv_grabcut_salient(const float *rgb, int w, int h, uint8_t *mask)
{
    try {
        cv::Mat f(h, w, CV_32FC3, const_cast<float *>(rgb)), img, sal, sal8;
        f.convertTo(img, CV_8UC3, 255.0);
        auto s = cv::saliency::StaticSaliencyFineGrained::create();
        if (!s->computeSaliency(img, sal))
            return -1;
        sal.convertTo(sal8, CV_8U, sal.depth() == CV_8U ? 1.0 : 255.0);
        cv::GaussianBlur(sal8, sal8, cv::Size(0, 0), 2.0 + 0.01 * std::max(w, h));
        /* the most salient sixth: probably the snake; the least salient half: probably not */
        std::vector<uchar> v(sal8.begin<uchar>(), sal8.end<uchar>());
        std::nth_element(v.begin(), v.begin() + v.size() * 5 / 6, v.end());
        uchar hi = v[v.size() * 5 / 6];
        std::nth_element(v.begin(), v.begin() + v.size() / 2, v.end());
        uchar lo = v[v.size() / 2];
        if (hi <= lo)
            return -1;
        cv::Mat m(h, w, CV_8UC1), bgd, fgd;
        for (int i = 0; i < w * h; i++)
            m.data[i] = sal8.data[i] >= hi ? cv::GC_PR_FGD : (sal8.data[i] <= lo ? cv::GC_BGD : cv::GC_PR_BGD);
        cv::setRNGSeed(GRABCUT_SEED);
        cv::grabCut(img, m, cv::Rect(), bgd, fgd, 5, cv::GC_INIT_WITH_MASK);
        for (int i = 0; i < w * h; i++)
            mask[i] = (m.data[i] == cv::GC_FGD || m.data[i] == cv::GC_PR_FGD) ? 255 : 0;
        return 0;
    } catch (...) {
        return -1;
    }
}

extern "C" int sq__cv_backdrop_out(const float *rgb, int w, int h, uint8_t *mask)
{
    enum { K = 8 };
    try {
        /* OpenCV (before 4.9) builds its CIELAB tables on the first conversion, unguarded:
         * once, before any two threads convert at the same time */
        static std::once_flag lab_tables;
        std::call_once(lab_tables, [] {
            cv::Mat one(1, 1, CV_32FC3, cv::Scalar(0.5, 0.5, 0.5)), out;
            cv::cvtColor(one, out, cv::COLOR_RGB2Lab);
        });
        cv::Mat f(h, w, CV_32FC3, const_cast<float *>(rgb)), lab, labels, centres;
        cv::cvtColor(f, lab, cv::COLOR_RGB2Lab);
        cv::setRNGSeed(GRABCUT_SEED);
        cv::kmeans(lab.reshape(1, w * h), K, labels, cv::TermCriteria(cv::TermCriteria::COUNT | cv::TermCriteria::EPS, 10, 0.5),
                   1, cv::KMEANS_PP_CENTERS, centres);
        size_t in[K] = {0}, all[K] = {0};
        for (int i = 0; i < w * h; i++) {
            const int c = labels.at<int>(i);
            all[c]++;
            in[c] += mask[i] != 0;
        }
        cv::Mat m(h, w, CV_8UC1, mask), cut = m.clone();
        for (int i = 0; i < w * h; i++) {
            const int c = labels.at<int>(i);
            if (2 * in[c] < all[c])
                cut.data[i] = 0;
        }
        /* a body colour shared with the backdrop (black rings on dark ground) went with
         * it: closed again over gaps of up to 1.5 body widths, within the mask */
        cv::Mat dist;
        cv::distanceTransform(cut, dist, cv::DIST_L2, 3);
        std::vector<float> d;
        for (int i = 0; i < w * h; i++)
            if (cut.data[i])
                d.push_back(dist.at<float>(i));
        if (d.empty()) {
            m.setTo(0);
            return 0;
        }
        std::nth_element(d.begin(), d.begin() + d.size() * 95 / 100, d.end());
        const int r = std::max(1, std::min((int)std::lround(1.5 * d[d.size() * 95 / 100]), std::max(w, h) / 8));
        cv::morphologyEx(cut, cut, cv::MORPH_CLOSE, cv::getStructuringElement(cv::MORPH_ELLIPSE, cv::Size(2 * r + 1, 2 * r + 1)));
        cv::bitwise_and(m, cut, m);
        return 0;
    } catch (...) {
        return -1;
    }
}

extern "C" int sq__cv_grabcut_band(const float *rgb, int w, int h, const uint8_t *band, const uint8_t *core,
                                   int reach, uint8_t *mask)
{
    try {
        cv::Mat b(h, w, CV_8UC1, const_cast<uint8_t *>(band)), near;
        cv::dilate(b, near, cv::getStructuringElement(cv::MORPH_ELLIPSE, cv::Size(2 * reach + 1, 2 * reach + 1)));
        /* the part that matters: the band and its surround, and as much again round it
         * for the backdrop's colours */
        cv::Rect box = cv::boundingRect(near);
        if (box.empty())
            return -1;
        box -= cv::Point(reach, reach);
        box += cv::Size(2 * reach, 2 * reach);
        box &= cv::Rect(0, 0, w, h);
        cv::Mat f(h, w, CV_32FC3, const_cast<float *>(rgb)), img;
        f(box).convertTo(img, CV_8UC3, 255.0);
        cv::Mat m(box.size(), CV_8UC1), bgd, fgd;
        for (int y = 0; y < box.height; y++)
            for (int x = 0; x < box.width; x++) {
                const size_t i = (size_t)(y + box.y) * w + (x + box.x);
                m.at<uchar>(y, x) = core[i] ? cv::GC_FGD : band[i] ? cv::GC_PR_FGD : near.data[i] ? cv::GC_PR_BGD : cv::GC_BGD;
            }
        /* GrabCut's time grows with the box's pixels: a wide body's box took it 3 to 20 s
         * at 1024 px. The box is cut at a scale that makes its longer side
         * BAND_SIDE pixels, as the automatic mask's GrabCut sees the photo, unless that
         * leaves the body less than BAND_REACH pixels of radius; the body found is scaled
         * back up. */
        const double scale = std::min(1.0, std::max((double)BAND_SIDE / std::max(box.width, box.height),
                                                    (double)BAND_REACH / std::max(reach, 1)));
        cv::Mat small = img, labels = m;
        if (scale < 1) {
            const cv::Size size(std::max(1, (int)std::lround(box.width * scale)),
                                std::max(1, (int)std::lround(box.height * scale)));
            cv::resize(img, small, size, 0, 0, cv::INTER_AREA);
            cv::resize(m, labels, size, 0, 0, cv::INTER_NEAREST);
        }
        cv::setRNGSeed(GRABCUT_SEED);
        cv::grabCut(small, labels, cv::Rect(), bgd, fgd, 5, cv::GC_INIT_WITH_MASK);
        cv::Mat body = (labels == cv::GC_FGD) | (labels == cv::GC_PR_FGD);
        if (scale < 1) {
            cv::resize(body, body, box.size(), 0, 0, cv::INTER_LINEAR);
            body = body >= 128;
        }
        std::memset(mask, 0, (size_t)w * h);
        for (int y = 0; y < box.height; y++)
            for (int x = 0; x < box.width; x++) {
                const size_t i = (size_t)(y + box.y) * w + (x + box.x);
                mask[i] = band[i] && body.at<uchar>(y, x) ? 255 : 0;
            }
        return 0;
    } catch (...) {
        return -1;
    }
}

extern "C" int sq__cv_clean_mask(uint8_t *mask, int w, int h, int radius, double max_hole)
{
    try {
        cv::Mat m(h, w, CV_8UC1, mask);
        if (radius > 0) {
            cv::Mat k = cv::getStructuringElement(cv::MORPH_ELLIPSE, cv::Size(2 * radius + 1, 2 * radius + 1));
            cv::morphologyEx(m, m, cv::MORPH_OPEN, k);
            cv::morphologyEx(m, m, cv::MORPH_CLOSE, k);
        }
        cv::Mat labels, stats, centroids;
        int n = cv::connectedComponentsWithStats(m, labels, stats, centroids, 8, CV_32S);
        int best = 0, area = 0;
        for (int i = 1; i < n; i++)
            if (stats.at<int>(i, cv::CC_STAT_AREA) > area) {
                area = stats.at<int>(i, cv::CC_STAT_AREA);
                best = i;
            }
        for (int y = 0; y < h; y++)
            for (int x = 0; x < w; x++)
                mask[y * w + x] = best > 0 && labels.at<int>(y, x) == best ? 255 : 0;
        /* small holes: background not reachable from the border, and small (a loop of
         * the body around the ground is not a hole) */
        cv::Mat inv = 255 - m, hl, hs, hc;
        int nh = cv::connectedComponentsWithStats(inv, hl, hs, hc, 4, CV_32S);
        for (int i = 1; i < nh; i++) {
            int x0 = hs.at<int>(i, cv::CC_STAT_LEFT), y0 = hs.at<int>(i, cv::CC_STAT_TOP);
            int x1 = x0 + hs.at<int>(i, cv::CC_STAT_WIDTH), y1 = y0 + hs.at<int>(i, cv::CC_STAT_HEIGHT);
            bool border = x0 == 0 || y0 == 0 || x1 == w || y1 == h;
            if (border || hs.at<int>(i, cv::CC_STAT_AREA) > max_hole)
                continue;
            for (int y = y0; y < y1; y++)
                for (int x = x0; x < x1; x++)
                    if (hl.at<int>(y, x) == i)
                        mask[y * w + x] = 255;
        }
        return n > 0 ? n - 1 : 0;
    } catch (...) {
        return -1;
    }
}

extern "C" int sq__cv_distance(const uint8_t *mask, int w, int h, float *dist)
{
    try {
        cv::Mat m(h, w, CV_8UC1, const_cast<uint8_t *>(mask)), d(h, w, CV_32FC1, dist);
        cv::distanceTransform(m, d, cv::DIST_L2, cv::DIST_MASK_5);
        return d.data == reinterpret_cast<uchar *>(dist) ? 0 : -1;
    } catch (...) {
        return -1;
    }
}
