// The commands of the printlight program, each declared once: its name,
// operands and one-line summary (for `printlight --help` and `printlight
// COMMAND --help`) and its entry point, which returns the exit code.
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
int reportCommand(const std::vector<std::string>& args);
int learnedDataCommand(const std::vector<std::string>& args);
int characteriseCommand(const std::vector<std::string>& args);

struct Command {
    const char* name;
    const char* operands;     // e.g. "SCENE.json"; "" for none
    const char* operandHelp;  // what they are
    const char* summary;
    int (*run)(const std::vector<std::string>& args);
};
const std::vector<Command>& commands();             // apps/printlight.cpp
const Command& commandNamed(const std::string& name);

// Thrown for bad command-line usage (exit code 2).
struct UsageError : std::exception {
    std::string message;
    explicit UsageError(std::string m) : message(std::move(m)) {}
    const char* what() const noexcept override { return message.c_str(); }
};
// Thrown for --help: the text to print (exit code 0).
struct HelpRequested {
    std::string text;
};

}  // namespace pl
