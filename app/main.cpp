// lacet: the command-line tool. `lacet --help` lists the commands.
#include <exception>
#include <iostream>

#include "app/commands.h"

int main(int argc, char** argv) {
    CLI::App app{"Lacet: vector-feature terrain editor (Bruneton & Neyret 2008)"};
    app.require_subcommand(1);
    lacet::app::addSynthCommand(app);
    lacet::app::addCheckCommand(app);
    lacet::app::addBenchCommand(app);
    lacet::app::addRenderCommand(app);
    lacet::app::addImportCommand(app);
    lacet::app::addEditCommand(app);
    lacet::app::addPyramidCommand(app);
    try {
        app.parse(argc, argv);
    } catch (const CLI::ParseError& e) {
        return app.exit(e);
    } catch (const std::exception& e) {
        std::cerr << "lacet: " << e.what() << "\n";
        return 1;
    }
    return 0;
}
