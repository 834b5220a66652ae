//! Keeping the k smallest items by a key, in a fixed buffer (used to pick
//! the nearest backtracking points and the nearest obstacle points).

/// Copies into `out` the `out.len()` items of `items` with the smallest
/// `key`, smallest first (ties keep input order); returns how many.
pub fn smallest_k<T: Copy>(items: &[T], out: &mut [T], key: impl Fn(&T) -> i64) -> usize {
    smallest_k_of(items.iter().copied(), out, key)
}

/// [`smallest_k`] over any sequence of items.
pub fn smallest_k_of<T: Copy>(
    items: impl Iterator<Item = T>,
    out: &mut [T],
    key: impl Fn(&T) -> i64,
) -> usize {
    let cap = out.len();
    let mut n = 0usize;
    for it in items {
        let it = &it;
        let k = key(it);
        let mut pos = n;
        while pos > 0 && out.get(pos - 1).is_some_and(|q| key(q) > k) {
            pos -= 1;
        }
        if pos >= cap {
            continue;
        }
        let end = if n < cap { n } else { cap - 1 };
        let mut j = end;
        while j > pos {
            if let Some(prev) = out.get(j - 1).copied() {
                if let Some(slot) = out.get_mut(j) {
                    *slot = prev;
                }
            }
            j -= 1;
        }
        if let Some(slot) = out.get_mut(pos) {
            *slot = *it;
        }
        if n < cap {
            n += 1;
        }
    }
    n
}
