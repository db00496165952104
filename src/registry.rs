//! The registry type every command takes: a leaf, so that `lib.rs` (which dispatches to the
//! commands) and the commands (which take a registry) do not import each other.

use harness::method::Method;

/// The methods a command line serves: the built-in `methods::REGISTRY`, or a crate's own list
/// (usually the built-in ones plus its methods). Entries are `'static` because work lists,
/// plans and workers hold them for a whole command; a method is a unit struct in a `static`.
pub type Registry<'r> = &'r [&'static dyn Method];
