// Subcommands of the printlight program. Each returns the process exit code.
#pragma once

#include <string>
#include <vector>

namespace pl {

int renderCommand(const std::vector<std::string>& args);
int infoCommand(const std::vector<std::string>& args);
int prepareCommand(const std::vector<std::string>& args);
int benchCommand(const std::vector<std::string>& args);
int batchCommand(const std::vector<std::string>& args);
int stabilityCommand(const std::vector<std::string>& args);
int predictCommand(const std::vector<std::string>& args);
int optimizeCommand(const std::vector<std::string>& args);

// Thrown for bad command-line usage (exit code 2).
struct UsageError : std::exception {
    std::string message;
    explicit UsageError(std::string m) : message(std::move(m)) {}
    const char* what() const noexcept override { return message.c_str(); }
};

}  // namespace pl
