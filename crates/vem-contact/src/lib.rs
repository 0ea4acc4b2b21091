//! vem-contact: work in progress; see the issue tracker.
#![deny(missing_docs)]
