//! The radix queue: the open list's [`Order::Monotone`] mode (issue 13,
//! search speed: "a cheaper open list … over integer costs").
//!
//! **What.** A monotone priority queue over `u32` keys (Ahuja, Mehlhorn,
//! Orlin and Tarjan, "Faster algorithms for the shortest path problem",
//! J. ACM 1990). It keeps the last key popped, `last`, and puts a key `k`
//! in bucket `b = bit length of (k XOR last)`: bucket 0 holds keys equal to
//! `last`, bucket `b` keys that first differ from it at bit `b - 1`. A pop
//! takes from bucket 0; when that is empty, the lowest non-empty bucket's
//! smallest key becomes `last` and that bucket's entries are spread over the
//! buckets below it. An entry only ever moves down, so it moves at most 32
//! times, and in practice once or twice: A* on a grid with integer costs
//! keeps every open key within two diagonal steps (2 × 8119) of `last`.
//!
//! **Why.** A* with a consistent heuristic (the integer octile one,
//! [`super::Algo::AStarOctile`]) pops keys that never decrease, which is all
//! a radix queue asks. A push and a pop are then a few instructions each
//! with no comparison chain, where the 4-ary heap sifts through `log4 n`
//! levels of four-way comparisons; on 8room_001 the heap holds thousands of
//! entries. A bucket per key (a "bucket queue") would be faster still but
//! needs one head per key in the span: 16,238 heads, 64 KiB, more than the
//! firmware can lend. The radix queue needs 33 heads. A refill walks its
//! bucket twice (for the least key, then to spread it); keeping each
//! bucket's least key would save the first walk (about 1 % of the
//! instructions; on the host, whose cache the walk misses, 5–8 % of the
//! time on 8room_001) for 132 bytes the firmware's stack needs more.
//!
//! **Memory.** None beyond 33 heads (152 bytes in all): the entries live in the open list's own
//! array, linked into their buckets through the entry's `g` field, which
//! this order does not otherwise keep (a popped entry reads `g = 0`). Slots
//! popped go onto a free list, so the capacity is the same as the heap's.
//!
//! **Ties** (our choice): among equal keys, those pushed while their key
//! is the least (a child whose f equals its parent's) come out last in first
//! out, ahead of those that reached the least through a refill, which come
//! out in the order they were pushed. A* then expands the newest cells of
//! the least f first, mostly the deeper ones, as the heap's larger-g rule
//! does; the path cost is optimal either way, only which of the equal-cost
//! paths is returned may differ. On Table 1's maps A* octile expands 767
//! nodes a query against 732 with the heap's order; on 8room_001, 19,075
//! against 19,061.
//!
//! **A key below `last`** cannot come from a consistent heuristic. If one is
//! pushed anyway it is raised to `last` (popped next), never lost and never
//! a panic: the search then stays complete but may lose optimality, which is
//! why only A* octile takes this order.

use super::{Entry, Full, OpenList, Order};

/// The end of a bucket's list (and of the free list).
const NIL: u32 = u32::MAX;
/// Bucket 0 for keys equal to `last`, buckets 1..=32 by the XOR's bit length.
const BUCKETS: usize = 33;

/// The radix queue's own state: the bucket heads and the free list.
#[derive(Clone, Copy, Debug)]
pub struct Buckets {
    heads: [u32; BUCKETS],
    /// Bit `b` set when bucket `b` is not empty.
    mask: u64,
    /// The last key popped (the smallest key the queue may hold).
    last: u32,
    /// Slots `top..CAP` of the array were never used since the clear.
    top: u32,
    /// The first slot freed by a pop, linked through `g`.
    free: u32,
}

impl Buckets {
    /// Empty buckets, `last` = 0.
    pub const fn new() -> Self {
        Self {
            heads: [NIL; BUCKETS],
            mask: 0,
            last: 0,
            top: 0,
            free: NIL,
        }
    }
}

impl Default for Buckets {
    fn default() -> Self {
        Self::new()
    }
}

/// The bucket of a key whose XOR with `last` is `x`.
#[inline]
fn bucket(x: u32) -> usize {
    (u32::BITS - x.leading_zeros()) as usize
}

impl<const CAP: usize> OpenList<CAP> {
    /// Pushes `key` for cell `idx` ([`Order::Monotone`]).
    #[inline]
    pub(super) fn radix_push(&mut self, key: u32, idx: u32) -> Result<(), Full> {
        debug_assert_eq!(self.order, Order::Monotone);
        let key = key.max(self.radix.last);
        let slot = self.alloc()?;
        self.link(slot, key, idx, bucket(key ^ self.radix.last));
        self.len += 1;
        self.peak = self.peak.max(self.len);
        Ok(())
    }

    /// Pops a smallest key ([`Order::Monotone`]).
    #[inline]
    pub(super) fn radix_pop(&mut self) -> Option<Entry> {
        if self.radix.mask & 1 == 0 {
            self.refill()?;
        }
        let slot = *self.radix.heads.first()?;
        let e = *self.items.get(slot as usize)?;
        let head = self.radix.heads.first_mut()?;
        *head = e.g;
        if e.g == NIL {
            self.radix.mask &= !1;
        }
        if let Some(freed) = self.items.get_mut(slot as usize) {
            freed.g = self.radix.free;
            self.radix.free = slot;
        }
        self.len = self.len.saturating_sub(1);
        Some(Entry {
            f: e.f,
            g: 0,
            idx: e.idx,
        })
    }

    /// A free slot: the free list's first, else the next never-used one.
    #[inline]
    fn alloc(&mut self) -> Result<u32, Full> {
        let r = &mut self.radix;
        if r.free != NIL {
            let slot = r.free;
            r.free = self.items.get(slot as usize).map_or(NIL, |e| e.g);
            return Ok(slot);
        }
        if (r.top as usize) < CAP {
            r.top += 1;
            return Ok(r.top - 1);
        }
        Err(Full)
    }

    /// Writes the entry into `slot` and links it at the head of bucket `b`.
    #[inline]
    fn link(&mut self, slot: u32, key: u32, idx: u32, b: usize) {
        let Some(head) = self.radix.heads.get_mut(b) else {
            return;
        };
        if let Some(e) = self.items.get_mut(slot as usize) {
            *e = Entry {
                f: key,
                g: *head,
                idx,
            };
            *head = slot;
            self.radix.mask |= 1 << b;
        }
    }

    /// Bucket 0 is empty: makes the lowest non-empty bucket's smallest key
    /// `last` and spreads that bucket below. `None` when the queue is empty.
    fn refill(&mut self) -> Option<()> {
        let b = self.radix.mask.trailing_zeros() as usize;
        let first = *self.radix.heads.get(b)?;
        let mut least = u32::MAX;
        let mut s = first;
        while let Some(e) = self.items.get(s as usize) {
            least = least.min(e.f);
            s = e.g;
        }
        self.radix.last = least;
        if let Some(h) = self.radix.heads.get_mut(b) {
            *h = NIL;
        }
        self.radix.mask &= !(1u64 << b);
        let mut s = first;
        while let Some(&e) = self.items.get(s as usize) {
            self.link(s, e.f, e.idx, bucket(e.f ^ least));
            s = e.g;
        }
        Some(())
    }
}
