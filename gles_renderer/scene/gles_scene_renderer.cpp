// SceneRenderer on an EGL context (surfaceless, or on a KMS display's GBM platform): background
// pass, mesh pass, readback or presentation to a window surface.
#include <algorithm>
#include <cmath>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "core/error.h"
#include "core/helper_thread.h"
#include "core/log.h"
#include "gles_renderer/gl/cpu_present.h"
#include "gles_renderer/gl/egl_context.h"
#include "gles_renderer/gl/frame_readback.h"
#include "gles_renderer/gl/gl_check.h"
#include "gles_renderer/gl/render_target.h"
#include "gles_renderer/gl/window_target.h"
#include "gles_renderer/ibl_gpu/environment_lighting.h"
#include "gles_renderer/overlay/overlay_pass.h"
#include "gles_renderer/scene/background_pass.h"
#include "gles_renderer/scene/camera_environment.h"
#include "gles_renderer/scene/camera_image.h"
#include "gles_renderer/scene/camera_projection.h"
#include "gles_renderer/scene/environment_probes.h"
#include "gles_renderer/scene/gpu_model.h"
#include "gles_renderer/scene/lens_effects.h"
#include "gles_renderer/scene/mesh_pass.h"
#include "gles_renderer/scene/model_pose_upload.h"
#include "gles_renderer/scene/phantom_depth.h"
#include "gles_renderer/scene/scene_renderer.h"
#include "gles_renderer/scene/shadow_pass.h"
#include "gles_renderer/scene/stage_timer.h"

namespace lumar {
namespace {

std::string glString(GLenum name)
{
    const auto* text = reinterpret_cast<const char*>(glGetString(name));
    return text ? text : "(unknown)";
}

// Makes the context current and logs what it runs on; returns it for member initialisation.
EglContext makeContext(const std::shared_ptr<EglDisplay>& display)
{
    EglContext context(display ? display : EglDisplay::surfaceless());
    LUMAR_LOG(Render, Info) << "GLES: " << glString(GL_VERSION) << ", renderer " << glString(GL_RENDERER) << ", vendor "
                            << glString(GL_VENDOR);
    return context;
}

void checkIntrinsics(const CameraIntrinsics& k, int width, int height)
{
    if (k.width != width || k.height != height)
        throw InputError("camera intrinsics are for " + std::to_string(k.width) + "x" + std::to_string(k.height) +
                         " but the renderer draws " + std::to_string(width) + "x" + std::to_string(height));
    if (!(std::isfinite(k.fx) && std::isfinite(k.fy) && k.fx > 0 && k.fy > 0 && std::isfinite(k.cx) &&
          std::isfinite(k.cy)))
        throw InputError("camera intrinsics need finite fx, fy > 0 and a finite principal point");
}

class GlesSceneRenderer final : public SceneRenderer {
public:
    GlesSceneRenderer(int width, int height, const RenderOptions& options)
        : context_(makeContext(options.display)), width_(width), height_(height),
          target_(width, height, options.samples), defaults_(makeDefaultTextures()),
          environment_(options.environmentMaps.ibl.mirrorSize), readback_(target_.readFramebuffer(), width, height),
          probes_(options.environmentMaps), shadows_(options.shadows),
          cameraPhantoms_(options.environmentMaps.dynamic && options.environmentMaps.phantomsShowCamera),
          mirrorSize_(options.environmentMaps.ibl.mirrorSize), materialTextureLimit_(options.materialTextureLimit),
          profile_(options.profile)
    {
        meshes_.setShadowMap(shadows_.map());
        if (options.lens.enabled) {
            lens_ = std::make_unique<LensEffects>(target_, options.lens, probes_.rgbm());
            lens_->useHelper(&helper_);
        }
        checkGlError("creating the scene renderer");
        // Zero-copy camera frames are imported from their dmabufs where this display can.
        background_.enableDmabufImport(options.display ? *options.display : *EglDisplay::surfaceless());
        LUMAR_LOG(Render, Info) << "rendering " << width << "x" << height << ", " << target_.samples()
                                << " sample(s) per pixel";
    }

    GlesSceneRenderer(const GlesSceneRenderer&) = delete;
    GlesSceneRenderer& operator=(const GlesSceneRenderer&) = delete;

    ~GlesSceneRenderer() override
    {
        // The GL objects below are deleted by their owners' destructors, which need this
        // context current (another renderer's may be).
        try {
            context_.makeCurrent();
        } catch (const RuntimeError& e) {
            LUMAR_LOG(Render, Warn) << "GL objects leak with their context: " << e.what();
        }
    }

    ModelId addModel(const GltfModel& model) override
    {
        context_.makeCurrent();
        models_.push_back(uploadModel(model, defaults_, materialTextureLimit_));
        models_.back().pose = makeGpuModelPose(model);
        LUMAR_LOG(Render, Debug) << "uploaded " << model.file.string() << " as model " << models_.size() - 1;
        return ModelId(models_.size() - 1);
    }

    void poseModel(ModelId model, std::span<const ClipTime> clips) override
    {
        if (model < 0 || size_t(model) >= models_.size())
            throw InputError("poseModel: model " + std::to_string(model) + " does not exist (the renderer has " +
                             std::to_string(models_.size()) + ")");
        GpuModel& gpu = models_[size_t(model)];
        if (!gpu.pose) {
            if (!clips.empty())
                throw InputError("poseModel: model " + std::to_string(model) + " has no animations");
            return;
        }
        StageTimer timer(profiler(), false);
        context_.makeCurrent();
        poseGpuModel(gpu, clips);
        timer.split(animation_);
    }

    void removeModels() override
    {
        context_.makeCurrent();
        probes_.clear();
        shadows_.invalidate();
        models_.clear();
    }

    void forgetFrames() override
    {
        context_.makeCurrent();
        probes_.forgetFrames();
        shadows_.invalidate();
        if (cameraEnvironment_)
            cameraEnvironment_->reset();
        captureFrame_ = 0;
        orientationTracked_ = false;
    }

    void setEnvironment(const ImageF& equirect, float intensity) override
    {
        context_.makeCurrent();
        environment_.set(equirect, intensity);
        captureFrame_ = 0; // a camera source's maps are refreshed with it at once
    }

    void setEnvironmentRotation(const glm::dmat3& environmentFromCamera) override
    {
        environment_.setRotation(environmentFromCamera);
        orientationTracked_ = true;
    }

    void setEnvironmentSource(EnvironmentSource source) override
    {
        context_.makeCurrent();
        if (source != EnvironmentSource::Hdr) {
            if (!cameraEnvironment_)
                cameraEnvironment_ = std::make_unique<CameraEnvironment>(probes_.rgbm());
            cameraEnvironment_->reset();
            captureFrame_ = 0;
        } else if (environmentSource_ != EnvironmentSource::Hdr) {
            probes_.markEnvironmentStale();
        }
        environmentSource_ = source;
    }

    void setExposure(float scale) override
    {
        if (!(std::isfinite(scale) && scale > 0.0f))
            throw InputError("exposure scale must be positive and finite, got " + std::to_string(scale));
        exposure_ = scale;
        cameraExposure_ = scale;
    }

    void setCameraImageExposure(float scale) override
    {
        if (!(std::isfinite(scale) && scale > 0.0f))
            throw InputError("camera image exposure must be positive and finite, got " + std::to_string(scale));
        cameraExposure_ = scale;
    }

    void setLight(const DirectionalLight& light) override { shadows_.setLight(light); }

    void render(const Image8& backgroundRgb, const CameraIntrinsics& intrinsics,
                std::span<const DrawItem> items) override
    {
        renderOver(&backgroundRgb, intrinsics, items, [&] { background_.drawUploaded(); });
    }

    void render(const YCbCrImage& background, const CameraIntrinsics& intrinsics,
                std::span<const DrawItem> items) override
    {
        renderOver(nullptr, intrinsics, items, [&] { background_.draw(background); });
    }

    void drawOverlay(const OverlayScene& overlay) override
    {
        if (overlay.empty())
            return;
        context_.makeCurrent();
        if (!overlay_)
            overlay_ = std::make_unique<OverlayPass>(); // on first use: off costs nothing
        overlay_->draw(overlay, target_.readFramebuffer(), width_, height_);
        glFlush();
    }

    void readback(Image8& rgb) override
    {
        context_.makeCurrent();
        readback_.read(rgb);
    }

    void present(WindowTarget& window) override
    {
        if (const auto pixels = window.cpuPixels()) {
            // Shown from memory (a software rasteriser's X11 window): no EGL surface.
            context_.makeCurrent();
            if (!cpuPresenter_)
                cpuPresenter_ = std::make_unique<CpuPresenter>();
            cpuPresenter_->write(target_.readFramebuffer(), width_, height_, window, *pixels);
            window.showSwapped();
            return;
        }
        context_.makeCurrent(window.surface());
        // Fit the frame into the window keeping its aspect (black bars), flipping it: the
        // frame's row 0 is the image's top, the window's is its bottom.
        const FittedRect fitted = fitFrame(width_, height_, window.width(), window.height());
        const int w = fitted.width, h = fitted.height, x = fitted.x, y = fitted.y;
        glBindFramebuffer(GL_DRAW_FRAMEBUFFER, 0);
        glBindFramebuffer(GL_READ_FRAMEBUFFER, target_.readFramebuffer());
        if (w != window.width() || h != window.height()) {
            glClearColor(0.0f, 0.0f, 0.0f, 1.0f);
            glClear(GL_COLOR_BUFFER_BIT);
        }
        glBlitFramebuffer(0, 0, width_, height_, x, y + h, x + w, y, GL_COLOR_BUFFER_BIT,
                          w == width_ && h == height_ ? GL_NEAREST : GL_LINEAR);
        checkGlError("copying the frame into the window");
        if (window.finishBeforeSwap())
            glFinish();
        const EGLDisplay display = eglGetCurrentDisplay();
        if (!eglSwapBuffers(display, window.surface()))
            throw RuntimeError("eglSwapBuffers failed on the display's window surface");
        window.showSwapped();
    }

    [[nodiscard]] RenderStats lastStats() const override { return stats_; }
    [[nodiscard]] const IblMaps* objectMaps(int object) const override { return probes_.objectMaps(object); }
    [[nodiscard]] const IblMaps& environmentMaps() const override { return probes_.environmentMaps(); }
    [[nodiscard]] double environmentCoverage() override
    {
        if (environmentSource_ == EnvironmentSource::Hdr)
            return 0.0;
        context_.makeCurrent();
        return cameraEnvironment_->coverage();
    }

    [[nodiscard]] int width() const override { return width_; }
    [[nodiscard]] int height() const override { return height_; }

private:
    // One frame: the environment maps, then `drawBackground` into the target, then the models.
    // `frame`: the camera image in memory, uploaded here, and the maps' camera image reduced
    // from it; drawBackground then draws what was uploaded. Null where drawBackground uploads
    // the camera image itself.
    template <typename DrawBackground>
    void renderOver(const Image8* frame, const CameraIntrinsics& intrinsics, std::span<const DrawItem> items,
                    const DrawBackground& drawBackground)
    {
        checkIntrinsics(intrinsics, width_, height_);
        for (const DrawItem& item : items)
            if (item.model < 0 || size_t(item.model) >= models_.size())
                throw InputError("draw item refers to model " + std::to_string(item.model) + " but the renderer has " +
                                 std::to_string(models_.size()));
        context_.makeCurrent();

        stats_ = RenderStats{};
        stats_.animation = std::exchange(animation_, StageTime{});
        frame_.clipFromCamera = glm::mat4(clipFromCamera(intrinsics, width_, height_));
        shadows_.render(models_, items, environment_.environmentFromCamera(), profiler(), stats_);
        // The camera image first: the environment maps may show it (phantoms carry it).
        StageTimer backgroundTimer(profiler(), profile_);
        target_.bindForDrawing();
        glDepthMask(GL_TRUE);
        glClear(GL_DEPTH_BUFFER_BIT);
        // The camera image for the maps reduced from the frame in memory on the CPU, alongside
        // its upload, instead of from the target after it (CameraImage::reduce).
        const bool cameraFromFrame = frame != nullptr && needsCameraImage(items);
        if (frame != nullptr) {
            if (cameraFromFrame) {
                helper_.runAlongside([&] { cameraImage_.reduce(*frame); }, [&] { background_.upload(*frame); });
                cameraImage_.uploadReduced();
            } else {
                background_.upload(*frame);
            }
        }
        drawBackground();
        CameraView camera;
        if (needsCameraImage(items)) {
            if (!cameraFromFrame)
                cameraImage_.capture(target_);
            camera = {cameraImage_.texture(), frame_.clipFromCamera};
            camera.exposure = exposure_;
            if (cameraPhantoms_) {
                phantomDepth_.render(meshes_, models_, items, frame_.clipFromCamera);
                camera.phantomDepth = phantomDepth_.texture();
            }
        }
        if (profile_)
            backgroundTimer.split(stats_.background);
        if (environmentSource_ != EnvironmentSource::Hdr)
            captureEnvironment(camera);

        const std::span<const IblMaps* const> maps =
            probes_.update(models_, items, environment_, meshes_, shadows_, camera, profiler(), stats_);

        StageTimer timer(profiler(), profile_);
        target_.bindForDrawing();
        const glm::mat3 environmentFromCamera(environment_.environmentFromCamera());
        for (int c = 0; c < 3; ++c)
            frame_.environmentFromCamera[c] = glm::vec4(environmentFromCamera[c], 0.0f);
        frame_.frameParams = glm::vec4(1.0f, 0.0f, probes_.rgbm() ? 1.0f : 0.0f, exposure_);
        frame_.lensParams.x = lens_ ? lens_->threshold() : 0.0f;
        shadows_.fillView(frame_, glm::dmat4(1.0));
        shadows_.drawReceivers(frame_, models_, items, maps);
        if (profile_)
            timer.split(stats_.receivers);
        if (lens_)
            lens_->beginVirtual();
        if (profile_)
            meshes_.onTransparentStart([&] { timer.split(stats_.shading); });
        if (lens_)
            meshes_.onBlending([&](bool blending) { lens_->blendingVirtual(blending); });
        // Each model at its frame level of detail (framePrimitivesFor) for its size in pixels.
        meshes_.draw(frame_, models_, items, maps, -1,
                     shadows_.enabled() ? MeshPass::Phantoms::Skip : MeshPass::Phantoms::DepthOnly,
                     MeshPass::Detail::Full, std::max(intrinsics.fx, intrinsics.fy));
        meshes_.onTransparentStart(nullptr);
        meshes_.onBlending(nullptr);
        if (lens_) {
            lens_->endVirtual();
            if (profile_)
                timer.split(stats_.transparent);
            lens_->apply(target_, lens_->area(models_, items, frame_.clipFromCamera));
            if (profile_)
                timer.split(stats_.post);
        }
        target_.finishFrame();
        if (profile_ && !lens_)
            timer.split(stats_.transparent);
        // Start the rasteriser now (llvmpipe's worker threads), so CPU work the caller does
        // before readback() overlaps with it.
        glFlush();
        // The frame's programs are linked by now (MeshPass links its variants on first use):
        // Mesa then frees the GLSL compiler's built-in function library (~MB resident) until
        // the next compile, which builds it again. A no-op where nothing was compiled since.
        glReleaseShaderCompiler();
    }

    [[nodiscard]] RenderCpuClock* profiler() { return profile_ ? &cpuClock_ : nullptr; }

    // Whether this frame's passes look at the camera image from elsewhere.
    [[nodiscard]] bool needsCameraImage(std::span<const DrawItem> items) const
    {
        return environmentSource_ != EnvironmentSource::Hdr ||
               (cameraPhantoms_ && std::any_of(items.begin(), items.end(), [](const DrawItem& item) {
                    return item.phantom && !item.receiverOnly;
                }));
    }

    // The environment built from the camera: this frame's image added where the orientation
    // is tracked, and every kCameraEnvironmentEvery-th frame the real environment's maps
    // rendered from it.
    void captureEnvironment(const CameraView& camera)
    {
        StageTimer timer(profiler(), profile_);
        if (orientationTracked_)
            cameraEnvironment_->accumulate(camera, environment_.environmentFromCamera(), cameraExposure_);
        orientationTracked_ = false;
        if (captureFrame_++ % kCameraEnvironmentEvery == 0) {
            const GLuint fill = environmentSource_ == EnvironmentSource::CameraOverHdr ? environment_.equirect() : 0;
            probes_.refreshEnvironmentMaps(environment_, [&](int face) {
                cameraEnvironment_->drawSkybox(face, mirrorSize_, fill, environment_.equirectWidth(), camera,
                                               cameraExposure_);
            });
        }
        if (profile_)
            timer.split(stats_.environmentCapture);
    }

    // How often the real environment's maps are rendered from the camera's map (frames): a
    // rebuild (mirror, SH, glossy maps) costs about one object's map, and each object's phantom
    // layer is drawn again after it. car.toml on llvmpipe (2 cores, load 9), medians of 5
    // interleaved runs: frame 144 ms with the .hdr, 184 ms rebuilding every frame
    // (environment_capture 17 ms, env_maps 36 against 13), 162 ms every 4th (7 ms, 20).
    // Every 4th frame the maps lag the camera by 130 ms at 30 fps, less than the 8 frames
    // a texel's running average spans anyway.
    static constexpr long kCameraEnvironmentEvery = 4;

    // Declared first so it is destroyed last: every GL object below needs it.
    EglContext context_;
    int width_;
    int height_;
    RenderTarget target_;
    BackgroundPass background_{target_};
    MeshPass meshes_;
    DefaultTextures defaults_;
    EnvironmentLighting environment_;
    FrameReadback readback_;
    CameraImage cameraImage_{width_, height_};
    PhantomDepth phantomDepth_{cameraImage_.width(), cameraImage_.height()};
    float exposure_ = 1.0f;
    float cameraExposure_ = 1.0f;
    std::vector<GpuModel> models_;
    EnvironmentProbes probes_;
    ShadowPass shadows_;
    bool cameraPhantoms_; // phantoms carry the camera image in the environment maps
    int mirrorSize_;
    int materialTextureLimit_; // RenderOptions::materialTextureLimit
    EnvironmentSource environmentSource_ = EnvironmentSource::Hdr;
    std::unique_ptr<CameraEnvironment> cameraEnvironment_; // made for the first camera source
    bool orientationTracked_ = false;                      // setEnvironmentRotation() since the last frame
    long captureFrame_ = 0;
    bool profile_;
    RenderCpuClock cpuClock_; // read only with profile_
    StageTime animation_;     // poseModel() since the last frame
    RenderStats stats_;
    FrameUniforms frame_;
    // Runs the camera image's reduction while this thread uploads the frame.
    HelperThread helper_;
    std::unique_ptr<LensEffects> lens_;          // with RenderOptions::lens
    std::unique_ptr<OverlayPass> overlay_;       // made by the first drawOverlay()
    std::unique_ptr<CpuPresenter> cpuPresenter_; // made by the first present() from memory
};

} // namespace

std::unique_ptr<SceneRenderer> SceneRenderer::create(int width, int height)
{
    return create(width, height, RenderOptions{});
}

std::unique_ptr<SceneRenderer> SceneRenderer::create(int width, int height, const RenderOptions& options)
{
    return std::make_unique<GlesSceneRenderer>(width, height, options);
}

} // namespace lumar
