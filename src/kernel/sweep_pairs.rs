//! Which sweeps of the tunnel test a cell needs: a property of its sign
//! configuration and face decisions alone, so the contour tables hold it
//! (see [`super::tunnel`] for the sweeps themselves).

/// The diagonal pairs of `w`-edges a sweep looks at, `(k, kk, j, jj)`: edges
/// `k` and `kk` (from corner `k` to `k + 4`) are joined where the plane's
/// saddle determinant `a_k a_kk - a_j a_jj` is positive.
pub(super) const DIAGONALS: [(usize, usize, usize, usize); 2] = [(0, 3, 1, 2), (1, 2, 0, 3)];

/// Which sweeps can find a join for configuration `config` (bit `c` set:
/// corner `c` inside) with corner labels `labels`: bit `2 s + d` for the
/// diagonal pair `DIAGONALS[d]` on the inside (`s = 0`) or the outside
/// (`s = 1`). The sweep tests exactly these pairs. Depends on the
/// configuration and face decisions only, so the tables hold it.
///
/// A pair can join only if each of its edges has a corner of that sign and
/// those corners carry different labels. Nor can it join when its two
/// corners are the only ones of their sign and lie on one end face (MC case
/// 3 across the face `w = 0`; `w = 1` is the same with `t` and `1 - t`
/// swapped). In the sweep's values `h` (`g` inside, `-g` outside) write
/// `u = 1 - t`, `v = t`, `a, b` for the two corners, `-c, -d` for the other
/// two corners of that face and `-e, -h, -f, -p` for the far ends of the
/// edges of `a, b, c, d`, so that `c, d, e, h, f, p >= 0` (all `> 0`
/// outside, where ties belong to the region). Then
/// `D = (ab - cd) u^2 - (ah + eb + cp + fd) uv + (eh - fp) v^2`. Where both
/// edges are in the region, `ev <= au`, so `eh v^2 <= ah uv` and
/// `D <= (ab - cd) u^2 - (eb + cp + fd) uv - fp v^2`. The face decision that
/// separated the two corners says `ab <= cd` inside and `ab < cd` outside,
/// so `D > 0` (inside) never holds, nor `D >= 0` (outside: `v = 0` gives
/// `ab - cd < 0`, `v > 0` gives `-fp v^2 < 0`). These pairs are 7-9% of
/// the sweeps on the CTs of `../shared/data`.
///
/// Exact because the sweep sees the same signs as `config`: scaling to
/// integers or normalising never turns a nonzero value into zero. (Where
/// the sweep rounds, for values more than 248 bits apart,
/// rounding can make a case 3 pair look joined; leaving it out is then the
/// exact answer.)
pub fn may_join(config: u8, labels: &[u8; 8]) -> u8 {
    let inside = |c: usize| config >> c & 1 == 1;
    let mut pairs = 0;
    for (s, sign) in [true, false].into_iter().enumerate() {
        let corner = |k: usize| [k, k + 4].into_iter().find(|&c| inside(c) == sign);
        let members = if sign { config } else { !config };
        for (d, &(k, kk, _, _)) in DIAGONALS.iter().enumerate() {
            let end_face = (1u8 << k) | (1 << kk);
            if members == end_face || members == end_face << 4 {
                continue;
            }
            if let (Some(a), Some(b)) = (corner(k), corner(kk)) {
                if labels[a] != labels[b] {
                    pairs |= 1 << (2 * s + d);
                }
            }
        }
    }
    pairs
}
