//! Tangential history of the neighbour list's pairs (paper 000 eqs 4-5: the sliding displacement of
//! each interacting pair), stored as structure of arrays: one array per component, parallel to the
//! pair arrays. A batch of consecutive pairs then loads and stores each component with whole-vector
//! moves instead of a transpose of 3-vectors.

use serde::{Deserialize, Serialize};

use crate::Vec3;

/// One 3-vector per pair, component by component.
#[derive(Debug, Clone, Default, Serialize, Deserialize, PartialEq)]
pub struct PairHistory {
    pub x: Vec<f64>,
    pub y: Vec<f64>,
    pub z: Vec<f64>,
}

impl PairHistory {
    /// `n` zero vectors.
    pub fn zeros(n: usize) -> Self {
        PairHistory {
            x: vec![0.0; n],
            y: vec![0.0; n],
            z: vec![0.0; n],
        }
    }

    pub fn len(&self) -> usize {
        self.x.len()
    }

    pub fn is_empty(&self) -> bool {
        self.x.is_empty()
    }

    /// The history of pair `p`.
    #[inline]
    pub fn get(&self, p: usize) -> Vec3 {
        Vec3::new(self.x[p], self.y[p], self.z[p])
    }

    /// Sets the history of pair `p`.
    #[inline]
    pub fn set(&mut self, p: usize, h: Vec3) {
        (self.x[p], self.y[p], self.z[p]) = (h.x, h.y, h.z);
    }

    /// Every pair's history, in pair order.
    pub fn iter(&self) -> impl Iterator<Item = Vec3> + '_ {
        (0..self.len()).map(|p| self.get(p))
    }

    /// The histories of pairs `start..`, mutable (for one force block).
    pub(crate) fn tail_mut(&mut self, start: usize) -> HistoryMut<'_> {
        HistoryMut {
            x: &mut self.x[start..],
            y: &mut self.y[start..],
            z: &mut self.z[start..],
        }
    }
}

/// A mutable run of consecutive pairs' histories.
pub(crate) struct HistoryMut<'a> {
    pub x: &'a mut [f64],
    pub y: &'a mut [f64],
    pub z: &'a mut [f64],
}

impl<'a> HistoryMut<'a> {
    /// Splits before pair `at` (relative to this run).
    pub fn split_at_mut(self, at: usize) -> (HistoryMut<'a>, HistoryMut<'a>) {
        let (x0, x1) = self.x.split_at_mut(at);
        let (y0, y1) = self.y.split_at_mut(at);
        let (z0, z1) = self.z.split_at_mut(at);
        (
            HistoryMut {
                x: x0,
                y: y0,
                z: z0,
            },
            HistoryMut {
                x: x1,
                y: y1,
                z: z1,
            },
        )
    }

    /// The components of pairs `at..at + len` copied into the first `len` lanes of `out` (a full
    /// batch with fixed-size moves, a partial one with slice copies).
    #[inline(always)]
    pub fn load<const N: usize>(&self, at: usize, len: usize, out: &mut [[f64; N]; 3]) {
        let src = [&*self.x, &*self.y, &*self.z];
        for (o, s) in out.iter_mut().zip(src) {
            if len == N {
                *o = s[at..at + N].try_into().expect("N pairs");
            } else {
                o[..len].copy_from_slice(&s[at..at + len]);
            }
        }
    }

    /// Stores the first `len` lanes of `src` as the components of pairs `at..at + len`.
    #[inline(always)]
    pub fn store<const N: usize>(&mut self, at: usize, len: usize, src: &[[f64; N]; 3]) {
        let dst = [&mut *self.x, &mut *self.y, &mut *self.z];
        for (d, s) in dst.into_iter().zip(src) {
            let d: &mut [f64] = &mut d[at..at + len];
            if len == N {
                let d: &mut [f64; N] = d.try_into().expect("N pairs");
                *d = *s;
            } else {
                d.copy_from_slice(&s[..len]);
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn runs_split_load_and_store_the_right_pairs() {
        let mut h = PairHistory::zeros(10);
        for p in 0..10 {
            h.set(p, Vec3::new(p as f64, 10.0 + p as f64, 20.0 + p as f64));
        }
        let (a, mut b) = h.tail_mut(2).split_at_mut(3);
        assert_eq!((a.x.len(), b.x.len()), (3, 5));
        let mut lanes = [[0.0; 2]; 3];
        b.load(1, 2, &mut lanes);
        assert_eq!(lanes, [[6.0, 7.0], [16.0, 17.0], [26.0, 27.0]]);
        b.load(4, 1, &mut lanes);
        assert_eq!(lanes, [[9.0, 7.0], [19.0, 17.0], [29.0, 27.0]]);
        b.store(0, 1, &[[-1.0, 0.5], [-2.0, 0.5], [-3.0, 0.5]]);
        assert_eq!(h.get(5), Vec3::new(-1.0, -2.0, -3.0));
        assert_eq!(h.get(6), Vec3::new(6.0, 16.0, 26.0));
        assert_eq!(h.iter().count(), 10);
    }
}
