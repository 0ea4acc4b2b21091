//! Cross-crate tests of the workspace live in `tests/tests/`: they build problems from the
//! manufactured solutions of `vem-verify` and check the contact layer against them.
