//! Room for the vectors of an in-memory mesh, which grow chunk by chunk
//! while nobody knows the mesh's size: [`reserve_for_planes`] and
//! [`fit`].
//!
//! Growing a vector moves it, unless the allocator can move its pages
//! instead of their bytes. A vector that grew by copies wrote the mesh
//! again into fresh pages at every step (on cthead, a tenth of an
//! in-memory extraction went there), so the first reservation here is at
//! least [`FIRST_ROOM`] bytes: address space, not memory, as the pages are
//! only backed when written. glibc (and the other common allocators) serve
//! a request that large with a mapping of its own and grow it by remapping
//! its pages, so the bytes are written once. [`fit`] gives the room no
//! vertex took back before the vector is handed on.

use crate::error::make_room;
use crate::Result;

/// The least room, in bytes, the first growth of a vector reserves: 32
/// MiB, the most that glibc's adaptive threshold for serving a request
/// with a mapping of its own (`M_MMAP_THRESHOLD`) can reach, so that a
/// request of this size is always mapped, whatever the process allocated
/// and freed before.
pub const FIRST_ROOM: usize = 32 << 20;

/// Makes room in `v` for `n` more items, where `v` collects a mesh chunk
/// by chunk and the last chunk came from grid plane `plane` of `planes`
/// (0: not known). When `v` is full it grows to the extrapolation of its
/// length over all planes (a quarter more), at least to [`FIRST_ROOM`]
/// bytes, or to what the allocator's doubling gives if that is more or the
/// reservation cannot be had; [`crate::Error::OutOfMemory`] (naming
/// `what`) if no room can be had at all.
pub fn reserve_for_planes<T>(
    v: &mut Vec<T>,
    n: usize,
    plane: u64,
    planes: u64,
    what: &str,
) -> Result<()> {
    if v.capacity() - v.len() >= n {
        return Ok(());
    }
    let needed = (v.len() + n) as u64;
    let done = plane.saturating_add(1).min(planes).max(1);
    let predicted = needed.saturating_mul(planes.max(done)) / done;
    let wanted = (predicted.saturating_add(predicted / 4) as usize)
        .max(FIRST_ROOM / std::mem::size_of::<T>().max(1));
    if wanted > v.capacity() * 2 && v.try_reserve_exact(wanted - v.len()).is_ok() {
        return Ok(());
    }
    make_room(v, n, what)
}

/// Gives back the room `v` holds beyond its length when that is more than
/// an eighth of it (the rest of a [`FIRST_ROOM`] reservation, or of a
/// prediction that overshot), before `v` is handed on: a mapped vector
/// shrinks where it is, without a copy.
pub fn fit<T>(v: &mut Vec<T>) {
    if v.capacity() - v.len() > v.capacity() / 8 {
        v.shrink_to_fit();
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn first_growth_reserves_the_first_room_and_fit_gives_it_back() {
        let mut v: Vec<[f32; 3]> = Vec::new();
        reserve_for_planes(&mut v, 10, 0, 100, "test").unwrap();
        assert!(v.capacity() >= FIRST_ROOM / 12);
        v.extend(std::iter::repeat_n([1.0; 3], 10));
        fit(&mut v);
        assert_eq!(v.len(), 10);
        assert!(v.capacity() < 100);
    }

    #[test]
    fn growth_follows_the_planes_prediction() {
        // 4 KiB items: the first room holds 8192 of them; reserved, never written.
        let mut v: Vec<[u8; 4096]> = Vec::new();
        reserve_for_planes(&mut v, 1000, 9, 100, "test").unwrap();
        // 1000 items after 10 of 100 planes predict 10000, and a quarter more.
        assert!(v.capacity() >= 12_500, "{}", v.capacity());
        assert!(v.capacity() < 20_000, "{}", v.capacity());
    }
}
