// bop-keys PREFIX: makes a CURVE key pair for encrypted, server-authenticated sessions and writes
// PREFIX.key (secret, mode 0600) and PREFIX.pub (public), each one 40-character z85 key.
// The server is started with the secret key; clients are given the public key.
#include "bop/common/ToolMain.hpp"
#include "security/CurveKeys.hpp"

#include <CLI/CLI.hpp>

#include <iostream>

int main(int argc, char** argv) {
    return bop::runTool("bop-keys", [&] {
        CLI::App app{
            "bop-keys: make a ZeroMQ CURVE key pair for BoP sessions. Writes PREFIX.key (the secret "
            "key, readable by its owner only; give it to the server) and PREFIX.pub (the public key; "
            "give it to clients, which check the server with it). Each file holds one 40-character "
            "z85 key and a newline."};
        std::string prefix;
        bool force = false;
        app.add_option("prefix", prefix, "path and name of the pair without extension, e.g. keys/server")->required();
        app.add_flag("-f,--force", force, "replace existing PREFIX.key and PREFIX.pub");
        CLI11_PARSE(app, argc, argv);

        const bop::protocol::CurveKeyPair keys = bop::protocol::makeCurveKeyPair();
        bop::protocol::writeCurveKeyFiles(prefix, keys, force);
        std::cout << "wrote " << prefix << ".key (secret, mode 0600) and " << prefix
                  << ".pub (public: " << keys.publicKey << ")\n";
        return 0;
    });
}
