// lumar markers: printable AprilTags at their exact physical size (markers/), and for a
// board the [[maps]] entry that describes what was printed.
#include <chrono>
#include <cstdio>
#include <fstream>

#include "commands.h"
#include "core/error.h"
#include "core/log.h"
#include "markers/marker_sheet.h"
#include "markers/sheet_renderer.h"
#include "markers/tag_pattern.h"
#include "usage_error.h"

namespace lumar {

int markersCommand(const MarkersCommandOptions& options)
{
    configureLogLevel(options.logLevel);
    const auto start = std::chrono::steady_clock::now();
    const TagFamilyPatterns family(options.family);
    MarkerRequest request;
    request.ids = parseIdList(options.ids, family);
    request.size = options.size;
    request.paper = paperNamed(options.page);
    request.mapName = options.mapName;
    if (!options.board.empty()) {
        request.board = parseBoardShape(options.board);
        request.board->spacing = options.spacing ? *options.spacing : minimumBoardSpacing(options.size, family);
    } else if (options.spacing || options.mapOut) {
        throw UsageError(std::string(options.spacing ? "--spacing" : "--map-out") + " needs --board");
    }
    const MarkerSheet sheet = layOutMarkers(request, family);
    const std::vector<std::filesystem::path> files = writeMarkerSheet(sheet, family, options.out, int(options.dpi));

    for (size_t i = 0; i < files.size(); ++i)
        if (files.size() == 1)
            std::printf("%s: %zu %s page%s\n", files[i].c_str(), sheet.pages.size(), sheet.paper.name.c_str(),
                        sheet.pages.size() == 1 ? "" : "s");
        else
            std::printf("%s: page %zu of %zu (%s)\n", files[i].c_str(), i + 1, files.size(), sheet.paper.name.c_str());
    if (request.board) {
        std::filesystem::path mapFile = std::filesystem::path(options.mapOut ? *options.mapOut : options.out);
        if (!options.mapOut)
            mapFile.replace_extension(".toml");
        std::ofstream out(mapFile);
        out << boardMapToml(request, family);
        out.close();
        if (!out)
            throw RuntimeError(mapFile.string() + ": cannot write");
        std::printf("%s: [[maps]] \"%s\" with %zu tags\n", mapFile.c_str(), request.mapName.c_str(),
                    request.ids.size());
    }
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    LUMAR_LOG(Output, Info) << request.ids.size() << " tags written in " << seconds << " s";
    return kExitOk;
}

} // namespace lumar
