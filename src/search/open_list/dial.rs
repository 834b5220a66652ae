//! The dial: the open list's [`Order::Monotone`] mode (issue 13, search
//! speed: "a cheaper open list … over integer costs").
//!
//! **What.** A bucket queue over `u32` keys in a ring of [`RING`] buckets,
//! each [`WIDTH`] keys wide (Dial 1969; the two-level form of Denardo and
//! Fox 1979, "Shortest-route methods: 1. Reaching, pruning, and buckets").
//! It keeps the last key popped, `last`, and a list of the entries whose key
//! is `last` (the current list). A key `k > last` goes to bucket
//! `(k / WIDTH) mod RING`. A pop takes the current list's head; when that
//! list is empty, the next non-empty bucket round the ring from `last`'s is
//! opened: its least key becomes `last`, and its entries of that key become
//! the current list (all of them, without relinking, when the bucket holds
//! one key only, which is the common case).
//!
//! **Why it is exact.** A* with a consistent heuristic (the integer octile
//! one, [`crate::search::Algo::AStarOctile`]) pushes keys in
//! `[last, last + SPREAD]`: a step changes g by its cost and h by at most
//! that cost, so a child's key exceeds its parent's (the last popped) by at
//! most two diagonal steps. [`RING`] buckets of [`WIDTH`] cover that span
//! plus the part of `last`'s bucket below `last`, so the ring, read from
//! `last`'s bucket onward, is in key order.
//!
//! **Why not the radix queue it replaces** (Ahuja, Mehlhorn, Orlin and
//! Tarjan 1990). The radix queue spreads a bucket over the buckets below it
//! at every refill, and an entry moved on average six times before it was
//! popped, each move a dependent read through the list: on 8room_001 a
//! quarter of the host's time went to those walks. Here an entry is read
//! once when its bucket is opened, and moved again only when its bucket
//! held several keys (about 2 % of the buckets opened on 8room_001): 1.5
//! reads per push against 6, in a model of both on the same queries.
//!
//! **Memory.** 64 list heads and six words (284 bytes): the entries live in
//! the open list's own array, linked through the entry's `g` field, which
//! this order does not otherwise keep (a popped entry reads `g = 0`). Slots
//! popped go onto a free list, so the capacity is the same as the heap's.
//!
//! **Ties** (our choice): among equal keys, the last pushed comes out first
//! (the deeper cell, as the heap's larger-g rule prefers), except that the
//! entries of a bucket that held several keys come out oldest first once it
//! is split. The path cost is optimal either way; only which of the
//! equal-cost paths is returned may differ.
//!
//! **Keys out of the span** cannot come from a consistent heuristic (the
//! first key pushed since the clear sets `last`, so the start's key is
//! always in it). A key
//! below `last` is raised to it (popped next); a key beyond `last + SPREAD`
//! is lowered to that bound. Either way the entry is never lost and nothing
//! panics: the search stays complete but may lose optimality, which is why
//! only A* octile takes this order.

use super::{Entry, Full, OpenList, Order};
use crate::math::cost::COST_DIAGONAL;

/// The end of a list (a bucket, the current list, the free list).
const NIL: u32 = u32::MAX;
/// Buckets in the ring (one bit each in a `u64` mask).
pub const RING: usize = 64;
/// The widest spread of open keys above the last popped under a consistent
/// heuristic: two diagonal steps.
pub const SPREAD: u32 = 2 * COST_DIAGONAL;
/// Keys per bucket: the ring covers `SPREAD` plus one bucket.
pub const WIDTH: u32 = SPREAD.div_ceil(RING as u32 - 1);

const _COVERS: () = assert!(RING as u32 * WIDTH >= SPREAD + WIDTH);

/// The dial's own state: the ring's heads, the current list and the free
/// list.
#[derive(Clone, Copy, Debug)]
pub struct Dial {
    heads: [u32; RING],
    /// Bit `b` set when bucket `b` is not empty.
    mask: u64,
    /// The entries whose key is `last`, newest first.
    current: u32,
    /// The last key popped (the smallest key the queue may hold).
    last: u32,
    /// Slots `top..CAP` of the array were never used since the clear.
    top: u32,
    /// The first slot freed by a pop, linked through `g`.
    free: u32,
}

impl Dial {
    /// An empty dial, `last` = 0.
    pub const fn new() -> Self {
        Self {
            heads: [NIL; RING],
            mask: 0,
            current: NIL,
            last: 0,
            top: 0,
            free: NIL,
        }
    }
}

impl Default for Dial {
    fn default() -> Self {
        Self::new()
    }
}

/// The ring bucket of key `k`.
#[inline(always)]
fn bucket(k: u32) -> usize {
    ((k / WIDTH) as usize) % RING
}

impl<const CAP: usize> OpenList<CAP> {
    /// Pushes `key` for cell `idx` ([`Order::Monotone`]).
    #[inline]
    pub(crate) fn dial_push(&mut self, key: u32, idx: u32) -> Result<(), Full> {
        debug_assert_eq!(self.order, Order::Monotone);
        if self.dial.top == 0 {
            self.dial.last = key; // the first push since the clear sets the floor
        }
        let last = self.dial.last;
        let key = key.clamp(last, last.saturating_add(SPREAD));
        let slot = self.alloc()?;
        let head = if key == last {
            &mut self.dial.current
        } else {
            let b = bucket(key);
            self.mark(b);
            match self.dial.heads.get_mut(b) {
                Some(h) => h,
                None => &mut self.dial.current, // never: b < RING
            }
        };
        if let Some(e) = self.items.get_mut(slot as usize) {
            *e = Entry {
                f: key,
                g: *head,
                idx,
            };
            *head = slot;
        }
        self.len += 1;
        Ok(())
    }

    /// Marks bucket `b` not empty.
    #[inline(always)]
    fn mark(&mut self, b: usize) {
        self.dial.mask |= 1 << b;
    }

    /// The most entries held at once since the clear: popped slots are
    /// used again before new ones, so that is the slots ever used.
    pub(super) fn dial_peak(&self) -> usize {
        self.dial.top as usize
    }

    /// Pops a smallest key ([`Order::Monotone`]).
    #[inline]
    pub(crate) fn dial_pop(&mut self) -> Option<Entry> {
        if self.dial.current == NIL {
            self.open_next()?;
        }
        let slot = self.dial.current;
        let e = *self.items.get(slot as usize)?;
        self.dial.current = e.g;
        if let Some(freed) = self.items.get_mut(slot as usize) {
            freed.g = self.dial.free;
            self.dial.free = slot;
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
        let d = &mut self.dial;
        if d.free != NIL {
            let slot = d.free;
            d.free = self.items.get(slot as usize).map_or(NIL, |e| e.g);
            return Ok(slot);
        }
        if (d.top as usize) < CAP {
            d.top += 1;
            return Ok(d.top - 1);
        }
        Err(Full)
    }

    /// The current list is empty: opens the next non-empty bucket from
    /// `last`'s, makes its least key `last` and its entries of that key the
    /// current list. `None` when the queue is empty.
    fn open_next(&mut self) -> Option<()> {
        if self.dial.mask == 0 {
            return None;
        }
        let from = bucket(self.dial.last);
        let b = (from + self.dial.mask.rotate_right(from as u32).trailing_zeros() as usize) % RING;
        let first = core::mem::replace(self.dial.heads.get_mut(b)?, NIL);
        self.dial.mask &= !(1 << b);
        let mut least = self.items.get(first as usize)?.f;
        let mut mixed = false;
        let mut s = first;
        while let Some(e) = self.items.get(s as usize) {
            mixed |= e.f != least;
            least = least.min(e.f);
            s = e.g;
        }
        self.dial.last = least;
        if !mixed {
            self.dial.current = first;
            return Some(());
        }
        self.split(first, least, b);
        Some(())
    }

    /// Relinks the list from `first` (bucket `b`'s, which held several
    /// keys): the entries keyed `least` onto the current list, the rest
    /// back into bucket `b`.
    fn split(&mut self, first: u32, least: u32, b: usize) {
        let mut s = first;
        while let Some(e) = self.items.get_mut(s as usize) {
            let next = e.g;
            let head = if e.f == least {
                &mut self.dial.current
            } else {
                self.dial.mask |= 1 << b;
                match self.dial.heads.get_mut(b) {
                    Some(h) => h,
                    None => return,
                }
            };
            e.g = *head;
            *head = s;
            s = next;
        }
    }
}
