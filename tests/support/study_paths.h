// Paths the tests read: the committed studies and the test data. One
// definition each, outside any namespace so that every test file sees it:
// a unity build compiles a test executable's files as one (CMakeLists.txt).
#pragma once

#include <string>

inline const std::string kSource = CAMDYN_SOURCE_DIR;
inline const std::string kStudiesDir = kSource + "/studies";
inline const std::string kStudies = kStudiesDir + "/";
inline const std::string kQuickstart = kStudies + "quickstart.json";
inline const std::string kBouncingBall = kStudies + "periodic/bouncing_ball.json";
inline const std::string kChaoticBall = kStudies + "periodic/bouncing_ball_chaotic.json";
inline const std::string kDropStudy = kStudies + "identify_drop/";
inline const std::string kOptimizeJump = kStudies + "optimize_jump.json";
inline const std::string kTestData = CAMDYN_TEST_DATA_DIR;
inline const std::string kIdentifyData = kTestData + "/identify/";

/// Whether `text` holds `part`.
inline bool contains(const std::string& text, const std::string& part) { return text.find(part) != std::string::npos; }
