//! A hash for small integer keys (joint, cluster and endpoint ids, packed
//! realization types): one multiply-rotate per word (the Fx hash), instead of
//! std's SipHash, whose collision resistance the solver's own ids do not need.

use std::collections::HashMap;
use std::hash::{BuildHasherDefault, Hasher};

/// The Fx hash state (as in rustc): `h = (rotl(h, 5) ^ word) · K` per word.
#[derive(Clone, Copy, Debug, Default)]
pub struct IntHasher(u64);

const K: u64 = 0x517c_c1b7_2722_0a95;

impl IntHasher {
    fn add(&mut self, word: u64) {
        self.0 = (self.0.rotate_left(5) ^ word).wrapping_mul(K);
    }
}

impl Hasher for IntHasher {
    fn write(&mut self, bytes: &[u8]) {
        for chunk in bytes.chunks(8) {
            let mut word = [0u8; 8];
            word[..chunk.len()].copy_from_slice(chunk);
            self.add(u64::from_le_bytes(word));
        }
    }
    fn write_u8(&mut self, x: u8) {
        self.add(u64::from(x));
    }
    fn write_u64(&mut self, x: u64) {
        self.add(x);
    }
    fn write_u128(&mut self, x: u128) {
        self.add(x as u64);
        self.add((x >> 64) as u64);
    }
    fn write_usize(&mut self, x: usize) {
        self.add(x as u64);
    }
    fn finish(&self) -> u64 {
        self.0
    }
}

/// A `HashMap` keyed by the solver's own integers, hashed by [`IntHasher`].
pub type IntMap<K, V> = HashMap<K, V, BuildHasherDefault<IntHasher>>;

/// An empty [`IntMap`] with room for `n` entries.
pub fn int_map<K, V>(n: usize) -> IntMap<K, V> {
    IntMap::with_capacity_and_hasher(n, BuildHasherDefault::default())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn keys_map_to_their_values() {
        let mut m: IntMap<(usize, usize), usize> = int_map(4);
        for a in 0..50 {
            for b in 0..50 {
                m.insert((a, b), a * 100 + b);
            }
        }
        assert_eq!(m.len(), 2500);
        assert_eq!(m.get(&(7, 42)), Some(&742));
        assert_eq!(m.get(&(50, 0)), None);
    }
}
