//! What a thread keeps between calls: a bounded list of shared set-up
//! (a system's or a tangent's structure), the least recently used
//! dropped first, so that the rods a sweep rebuilds on one mesh find
//! theirs instead of building it again.

use std::cell::RefCell;
use std::sync::Arc;

/// At most `capacity` items, most recently used last. Held in a
/// `thread_local!`: each thread keeps its own (reentrant, no locks).
pub(crate) struct Recent<T> {
    items: RefCell<Vec<Arc<T>>>,
    capacity: usize,
}

impl<T> Recent<T> {
    pub(crate) const fn new(capacity: usize) -> Self {
        Recent { items: RefCell::new(Vec::new()), capacity }
    }

    /// The first kept item that `fits`, made the most recently used.
    /// `fits` only compares: it must not reach this list again.
    pub(crate) fn find(&self, fits: impl Fn(&T) -> bool) -> Option<Arc<T>> {
        let mut items = self.items.borrow_mut();
        let at = items.iter().position(|s| fits(s))?;
        let s = items.remove(at);
        items.push(s.clone());
        Some(s)
    }

    /// Keep `item`, dropping the least recently used one when full.
    pub(crate) fn keep(&self, item: Arc<T>) {
        let mut items = self.items.borrow_mut();
        if items.len() == self.capacity {
            items.remove(0);
        }
        items.push(item);
    }

    pub(crate) fn clear(&self) {
        self.items.borrow_mut().clear();
    }

    #[cfg(test)]
    pub(crate) fn len(&self) -> usize {
        self.items.borrow().len()
    }
}
