//! Scaling a cell's values by a power of two, which changes no sign, no
//! decision and no position as long as nothing underflows (every rounding
//! scales with the values), so that the kernel's products of up to four
//! values stay away from overflow and underflow.

/// `2^e` for `e` in the normal range of f64 (from the exponent bits, no
/// library call), `2^e` rounded by `powi` otherwise.
pub(super) fn power_of_two(e: i32) -> f64 {
    if (-1022..=1023).contains(&e) {
        f64::from_bits(((e + 1023) as u64) << 52)
    } else {
        2f64.powi(e)
    }
}

/// The values scaled by a power of two so the largest magnitude is near 1
/// (exact but for values more than 2^1074 times smaller than the largest,
/// which become the smallest number of their sign rather than zero, so that
/// every sign is kept; keeps degree-four products away from overflow and
/// underflow).
pub(super) fn normalized(g: &[f64; 8]) -> [f64; 8] {
    let scaled = scaled_down(g);
    std::array::from_fn(|c| {
        if scaled[c] == 0.0 && g[c] != 0.0 {
            f64::from_bits(1).copysign(g[c])
        } else {
            scaled[c]
        }
    })
}

/// The values scaled by the power of two that brings the largest magnitude
/// near 1 (rounded where it underflows).
fn scaled_down(g: &[f64; 8]) -> [f64; 8] {
    let max = g.iter().fold(0.0f64, |m, v| m.max(v.abs()));
    if max == 0.0 || !max.is_finite() {
        return *g;
    }
    // floor(log2(max)): the exponent bits of a normal number.
    let exp = if max >= f64::MIN_POSITIVE {
        ((max.to_bits() >> 52) & 0x7ff) as i32 - 1023
    } else {
        max.log2().floor() as i32
    };
    if exp > -1023 {
        let scale = power_of_two(-exp);
        g.map(|v| v * scale)
    } else {
        // A subnormal max: 2^-exp is beyond f64, so scale in two steps.
        let (half, rest) = (power_of_two(-exp / 2), power_of_two(-exp - -exp / 2));
        g.map(|v| v * half * rest)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn power_of_two_is_exact_over_the_whole_range() {
        for e in -1074..=1023 {
            assert_eq!(power_of_two(e), 2f64.powi(e), "2^{e}");
        }
    }

    #[test]
    fn normalized_puts_the_largest_magnitude_in_one_to_two() {
        for max in [1e-300, 3.0e-5, 0.99999999, 1.0, 7.5, 1e150, 1e-310] {
            let n = normalized(&[max, -max / 3.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0]);
            assert!((1.0..2.0).contains(&n[0]), "{max} -> {}", n[0]);
        }
    }
}
