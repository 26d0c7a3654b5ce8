// Catch2's main(), compiled once for every test executable (Catch2 v2 or v3).
#if RT_CATCH_V3
#include <catch2/catch_session.hpp>
int main(int argc, char* argv[]) { return Catch::Session().run(argc, argv); }
#else
#define CATCH_CONFIG_MAIN
#include <catch2/catch.hpp>
#endif
