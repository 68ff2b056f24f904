// SPDX-License-Identifier: Apache-2.0
// Compiles the tests' precompiled header (test_pch.hpp) once; every test reuses it.
