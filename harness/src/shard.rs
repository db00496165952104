//! Sharding a run for batch schedulers: `run --shard i/n` runs the i-th of n contiguous,
//! disjoint slices of the run's work list (scenes × methods × parameter sets, in the runner's
//! order), and `merge` puts the shards' results back together in shard order.
//!
//! Slices are contiguous rather than round-robin so each shard renders the references of
//! only the scenes it touches (references are the expensive cold-cache part), and so the
//! concatenation of shards 1..n is exactly the unsharded order. Sizes differ by at most one
//! item; they are balanced by count, not by cost.

use serde::{Deserialize, Serialize};

/// The i-th of n shards, 1-based like `jest --shard` and Playwright (`1/2` is the first half).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub struct Shard {
    /// 1..=count.
    pub index: u32,
    pub count: u32,
}

impl Shard {
    /// The whole work list (shard 1 of 1).
    pub const WHOLE: Shard = Shard { index: 1, count: 1 };

    /// Parses `i/n` with 1 ≤ i ≤ n.
    pub fn parse(s: &str) -> Result<Shard, String> {
        let bad = || format!("--shard '{s}': expected i/n with 1 ≤ i ≤ n (e.g. 1/4)");
        let (i, n) = s.split_once('/').ok_or_else(bad)?;
        let index: u32 = i.trim().parse().map_err(|_| bad())?;
        let count: u32 = n.trim().parse().map_err(|_| bad())?;
        if count == 0 || index == 0 || index > count {
            return Err(bad());
        }
        Ok(Shard { index, count })
    }

    pub fn is_whole(self) -> bool {
        self.count == 1
    }

    /// The half-open range of a work list of `len` items that this shard runs.
    pub fn range(self, len: usize) -> std::ops::Range<usize> {
        let (i, n) = (self.index as usize, self.count as usize);
        // u128 so len × n never overflows.
        let at = |k: usize| ((k as u128 * len as u128) / n as u128) as usize;
        at(i - 1)..at(i)
    }
}

impl std::fmt::Display for Shard {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "{}/{}", self.index, self.count)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn shards_partition_every_list_in_order() {
        for len in 0..40usize {
            for count in 1..9u32 {
                let mut next = 0;
                let mut sizes = Vec::new();
                for index in 1..=count {
                    let r = Shard { index, count }.range(len);
                    // Contiguous and in order: each starts where the previous ended.
                    assert_eq!(r.start, next, "len {len} shard {index}/{count}");
                    next = r.end;
                    sizes.push(r.len());
                }
                assert_eq!(next, len, "the shards cover the list");
                let (lo, hi) = (sizes.iter().min().unwrap(), sizes.iter().max().unwrap());
                assert!(hi - lo <= 1, "balanced: {sizes:?}");
            }
        }
    }

    #[test]
    fn parse_accepts_i_of_n_and_refuses_the_rest() {
        assert_eq!(Shard::parse("2/3"), Ok(Shard { index: 2, count: 3 }));
        assert_eq!(Shard::parse(" 1 / 1 "), Ok(Shard::WHOLE));
        for bad in ["0/2", "3/2", "1/0", "1", "a/b", "-1/2", "", "1/2/3"] {
            let e = Shard::parse(bad).unwrap_err();
            assert!(e.contains("i/n"), "{bad}: {e}");
        }
        assert_eq!(Shard { index: 2, count: 5 }.to_string(), "2/5");
    }
}
