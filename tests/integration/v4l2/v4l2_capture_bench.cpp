// Measures the V4L2 source per pixel format at 1280x720 against the virtual camera (run it
// with liblumar_vcam.so preloaded): the mean dequeued-buffer → RGB + luma time over 100
// frames, and the capturing thread's CPU use (getrusage RUSAGE_THREAD over the run / wall
// time) at 30 fps. The virtual camera synthesises its frames inside the capturing thread's
// own ioctl/poll calls, so that CPU figure includes the device's work too; the conversion
// alone is the part a real camera would cost. "/g" rows keep the NV12/YUYV planes for the
// renderer's GPU conversion (camera.convert = "gpu"), "/z" lend the buffers instead of copying
// them (camera.zero_copy = "auto"). Not a test: numbers for DESIGN.md §9.
//
//   LD_PRELOAD=build/tests/vcam/liblumar_vcam.so LUMAR_VCAM_DEVICE=/dev/video-bench
//   build/tests/integration/v4l2/v4l2_capture_bench [frames]       (one command line)
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <string>

#include <linux/videodev2.h>
#include <sys/resource.h>

#include "capture/v4l2/v4l2_source.h"
#include "core/log.h"

namespace {

double threadCpuSeconds()
{
    rusage usage{};
    getrusage(RUSAGE_THREAD, &usage);
    return double(usage.ru_utime.tv_sec + usage.ru_stime.tv_sec) +
           double(usage.ru_utime.tv_usec + usage.ru_stime.tv_usec) / 1e6;
}

} // namespace

int main(int argc, char** argv)
{
    const int frames = argc > 1 ? std::atoi(argv[1]) : 100;
    const char* device = std::getenv("LUMAR_VCAM_DEVICE");
    if (device == nullptr) {
        std::fprintf(stderr, "set LUMAR_VCAM_DEVICE and preload liblumar_vcam.so\n");
        return 2;
    }
    lumar::log::configure("*:warn");
    std::printf("%-6s %10s %10s %10s %12s\n", "format", "size", "convert", "(min)", "thread CPU");
    struct Case {
        const char* vcamFormats;
        const char* name;
        bool rawYcbcr = false; // planes kept for the GPU: copies plus luma, no RGB
        bool zeroCopy = false; // with rawYcbcr: the buffers lent, luma only
    };
    for (Case c : {Case{"NV12", "NV12"}, Case{"NV12", "NV12/g", true}, Case{"NV12", "NV12/z", true, true},
                   Case{"YUYV", "YUYV"}, Case{"YUYV", "YUYV/g", true}, Case{"YUYV", "YUYV/z", true, true},
                   Case{"MJPG", "MJPEG"}, Case{"GREY", "GREY"}}) {
        setenv("LUMAR_VCAM_FORMATS", c.vcamFormats, 1);
        lumar::V4l2Options options;
        options.device = device;
        options.width = 1280;
        options.height = 720;
        options.fps = 30.0;
        options.rawYcbcr = c.rawYcbcr;
        options.zeroCopy = c.zeroCopy;
        lumar::V4l2Source source(options);
        lumar::Frame frame;
        source.next(frame); // first frame: buffers sized, decoder warmed up
        double totalNs = 0.0;
        double minNs = 1e18;
        const double cpuStart = threadCpuSeconds();
        const auto wallStart = std::chrono::steady_clock::now();
        for (int i = 0; i < frames; ++i) {
            source.next(frame);
            totalNs += double(source.lastConversionNs());
            minNs = std::min(minNs, double(source.lastConversionNs()));
        }
        const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - wallStart).count();
        const double cpu = threadCpuSeconds() - cpuStart;
        std::printf("%-6s %4dx%-5d %8.2f ms %7.2f ms %10.1f %%   (corrupt %llu, dropped %llu)\n", c.name,
                    frame.luma.width, frame.luma.height, totalNs / frames / 1e6, minNs / 1e6, 100.0 * cpu / wall,
                    static_cast<unsigned long long>(source.framesCorrupt()),
                    static_cast<unsigned long long>(source.framesDropped()));
    }
    return 0;
}
