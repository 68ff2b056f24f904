// SPDX-License-Identifier: Apache-2.0
// Placeholder until its owner writes it.
