//! Which entry of each axis before z, y, x a chunked array is read at
//! (`--at c=1,t=0`): an OME-Zarr image of several channels or time points,
//! or an HDF5 dataset of several volumes, is one 3-D volume per entry, and
//! the user picks one instead of copying it out first.
//!
//! Axes are named as the file names them (OME-Zarr's `t`, `c`), or by
//! their position, 0 the slowest (any array): `--at 0=2`. An axis of one
//! entry needs no pick; an axis of several needs one, and the error says
//! how to give it. `volume_axes` also lets a pick name an axis after z,
//! y, x (a channel axis last, as ilastik writes `zyxc`: `--at 3=1`).

/// Where the volume lies in an array's axes ([`volume_axes`]): z, y, x are
/// axes `end - 3`, `end - 2`, `end - 1`; every other axis is read at one
/// entry.
#[derive(Debug, Clone, PartialEq, Eq)]
pub(crate) struct VolumeAxes {
    /// One past the x axis.
    pub end: usize,
    /// The entry read of each axis before z (`end - 3` of them).
    pub lead: Vec<u64>,
    /// The entry read of each axis after x (`shape.len() - end` of them).
    pub trail: Vec<u64>,
}

/// The volume's axes in an array of `shape` whose axes are `names`, and
/// the entry of every other axis, from the user's `picks`: axes after the
/// volume are set aside from the end while they have one entry or a pick
/// names them (a channel axis last: a `(z, y, x, 3)` dataset read with
/// `--at 3=1`); the last three left are z, y, x, and the axes before them
/// take their entries as [`entries`] gives them. Without a pick, a last
/// axis of several entries is the volume's x, as it always was; the error
/// for an axis before it then also says how to pick the last axis's entry
/// instead.
pub(crate) fn volume_axes(
    shape: &[u64],
    names: &[String],
    picks: &[(String, u64)],
) -> Result<VolumeAxes, String> {
    let at: Vec<Option<usize>> = picks
        .iter()
        .map(|(axis, _)| position(names, shape.len(), axis))
        .collect();
    let mut end = shape.len();
    while end > 3 && (shape[end - 1] == 1 || at.contains(&Some(end - 1))) {
        end -= 1;
    }
    // Picks of the axes set aside; the others go to `entries`.
    let mut trail: Vec<Option<u64>> = vec![None; shape.len() - end];
    let mut before = Vec::new();
    for ((axis, entry), at) in picks.iter().zip(&at) {
        match *at {
            Some(i) if i >= end => {
                if trail[i - end].is_some() {
                    return Err(format!("--at names axis '{}' twice", names[i]));
                }
                trail[i - end] = Some(checked_entry(axis, *entry, &names[i], shape[i])?);
            }
            _ => before.push((axis.clone(), *entry)),
        }
    }
    let lead = entries(&shape[..end], &names[..end], &before).map_err(|why| {
        let last = shape.len() - 1;
        match why.contains("pick one with --at") && end == shape.len() {
            true => format!(
                "{why}; or, if the last axis ('{}', {} entries) is a channel after z, y, x (as ilastik writes zyxc), pick its entry with --at {}=I",
                names[last], shape[last], names[last]
            ),
            false => why,
        }
    })?;
    // An axis set aside without a pick has one entry.
    let trail = trail.into_iter().map(|entry| entry.unwrap_or(0)).collect();
    Ok(VolumeAxes { end, lead, trail })
}

/// The position of the axis a pick names, by its name or its position (0
/// the slowest), among the first `rank` axes named `names`.
fn position(names: &[String], rank: usize, axis: &str) -> Option<usize> {
    (0..rank).find(|&i| names.get(i).is_some_and(|n| n == axis) || i.to_string() == axis)
}

/// `entry` of axis `name` (of `len` entries), picked as `--at AXIS=ENTRY`,
/// or the error when it lies past the axis.
fn checked_entry(axis: &str, entry: u64, name: &str, len: u64) -> Result<u64, String> {
    match entry < len {
        true => Ok(entry),
        false => Err(format!(
            "--at {axis}={entry}: axis '{name}' has {len} entries (0 to {})",
            len - 1
        )),
    }
}

/// The entry to read of each axis before the last three (z, y, x) of an
/// array of `shape` whose axes are `names` (one per axis, slowest first),
/// from the user's `picks` (axis, entry). An error, as one line, when a
/// pick names no such axis, names one twice or lies past its axis, or
/// when an axis of several entries has no pick.
pub(crate) fn entries(
    shape: &[u64],
    names: &[String],
    picks: &[(String, u64)],
) -> Result<Vec<u64>, String> {
    let lead = shape.len().saturating_sub(3);
    let leading: Vec<String> = (0..lead).map(|i| names[i].clone()).collect();
    let mut chosen: Vec<Option<u64>> = vec![None; lead];
    for (axis, entry) in picks {
        let i = match position(names, shape.len(), axis) {
            Some(i) if i < lead => i,
            Some(_) => {
                return Err(format!(
                    "--at {axis}={entry}: '{axis}' is one of the volume's own axes (z, y, x); --at picks an entry of an axis before them{}",
                    listed(&leading)
                ))
            }
            None => {
                return Err(format!(
                    "--at {axis}={entry}: the array has no axis '{axis}'{}",
                    listed(&leading)
                ))
            }
        };
        if chosen[i].is_some() {
            return Err(format!("--at names axis '{}' twice", names[i]));
        }
        chosen[i] = Some(checked_entry(axis, *entry, &names[i], shape[i])?);
    }
    (0..lead)
        .map(|i| match chosen[i] {
            Some(entry) => Ok(entry),
            None if shape[i] == 1 => Ok(0),
            None => Err(format!(
                "axis '{}' has {} entries, and tmc reads one 3-D volume (z, y, x): pick one with --at {}=I (I from 0 to {})",
                names[i],
                shape[i],
                names[i],
                shape[i] - 1
            )),
        })
        .collect()
}

/// The axes a pick may name, for an error message.
fn listed(leading: &[String]) -> String {
    match leading.is_empty() {
        true => " (it has no axis before z, y, x)".into(),
        false => format!(" (its axes before z, y, x: {})", leading.join(", ")),
    }
}

/// Parses one of `--at`'s pairs, `AXIS=ENTRY`.
pub fn parse_pick(pair: &str) -> Result<(String, u64), String> {
    let (axis, entry) = pair
        .split_once('=')
        .ok_or_else(|| format!("'{pair}' is not AXIS=ENTRY (e.g. c=1)"))?;
    let axis = axis.trim();
    if axis.is_empty() {
        return Err(format!("'{pair}' names no axis (e.g. c=1)"));
    }
    let entry = entry
        .trim()
        .parse::<u64>()
        .map_err(|_| format!("'{pair}': the entry must be a whole number from 0 (e.g. c=1)"))?;
    Ok((axis.to_string(), entry))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn names(n: &[&str]) -> Vec<String> {
        n.iter().map(|s| s.to_string()).collect()
    }

    #[test]
    fn picks_by_name_or_position_and_singletons_need_none() {
        let axes = names(&["t", "c", "z", "y", "x"]);
        let shape = [1, 3, 4, 5, 6];
        let pick = |p: &[(&str, u64)]| {
            let p: Vec<_> = p.iter().map(|&(a, e)| (a.to_string(), e)).collect();
            entries(&shape, &axes, &p)
        };
        assert_eq!(pick(&[("c", 2)]), Ok(vec![0, 2]));
        assert_eq!(pick(&[("1", 1), ("t", 0)]), Ok(vec![0, 1]));
        let none = pick(&[]).unwrap_err();
        assert!(
            none.contains("pick one with --at c=I (I from 0 to 2)"),
            "{none}"
        );
        assert!(pick(&[("c", 3)])
            .unwrap_err()
            .contains("has 3 entries (0 to 2)"));
        assert!(pick(&[("t", 1), ("c", 0)])
            .unwrap_err()
            .contains("1 entries (0 to 0)"));
        assert!(pick(&[("c", 0), ("1", 1)]).unwrap_err().contains("twice"));
        let own = pick(&[("z", 1)]).unwrap_err();
        assert!(
            own.contains("volume's own axes") && own.contains("t, c"),
            "{own}"
        );
        assert!(pick(&[("q", 1)]).unwrap_err().contains("no axis 'q'"));
        // A 3-D array has nothing to pick.
        let three = entries(&[4, 5, 6], &names(&["z", "y", "x"]), &[]);
        assert_eq!(three, Ok(vec![]));
        let err = entries(&[4, 5, 6], &names(&["0", "1", "2"]), &[("0".into(), 1)]);
        assert!(err.unwrap_err().contains("no axis before z, y, x"));
    }

    #[test]
    fn a_pick_sets_an_axis_after_x_aside() {
        let axes = names(&["0", "1", "2", "3", "4"]);
        let pick = |shape: &[u64], p: &[(&str, u64)]| {
            let p: Vec<_> = p.iter().map(|&(a, e)| (a.to_string(), e)).collect();
            volume_axes(shape, &axes[..shape.len()], &p)
        };
        let axes_of = |end, lead: &[u64], trail: &[u64]| VolumeAxes {
            end,
            lead: lead.to_vec(),
            trail: trail.to_vec(),
        };
        // zyxc: the channel picked, or of one entry.
        assert_eq!(pick(&[4, 5, 6, 3], &[("3", 2)]), Ok(axes_of(3, &[], &[2])));
        assert_eq!(pick(&[4, 5, 6, 1], &[]), Ok(axes_of(3, &[], &[0])));
        // tzyxc: both sides.
        assert_eq!(
            pick(&[2, 4, 5, 6, 3], &[("4", 1), ("0", 1)]),
            Ok(axes_of(4, &[1], &[1]))
        );
        // Without a pick the last axis is x, and the error says how to pick it.
        let err = pick(&[4, 5, 6, 3], &[]).unwrap_err();
        assert!(
            err.contains("--at 0=I") && err.contains("--at 3=I"),
            "{err}"
        );
        assert_eq!(pick(&[4, 5, 6, 3], &[("0", 1)]), Ok(axes_of(4, &[1], &[])));
        let past = pick(&[4, 5, 6, 3], &[("3", 3)]).unwrap_err();
        assert!(past.contains("has 3 entries (0 to 2)"), "{past}");
        let twice = pick(&[4, 5, 6, 3], &[("3", 0), ("3", 1)]).unwrap_err();
        assert!(twice.contains("twice"), "{twice}");
        // A 3-D array keeps its three axes: a pick of one is refused.
        let own = pick(&[4, 5, 6], &[("2", 1)]).unwrap_err();
        assert!(own.contains("volume's own axes"), "{own}");
    }

    #[test]
    fn the_option_parses_pairs() {
        assert_eq!(parse_pick(" t = 0"), Ok(("t".to_string(), 0)));
        assert!(parse_pick("c").is_err());
        assert!(parse_pick("=1").is_err());
        assert!(parse_pick("c=-1").is_err());
        assert!(parse_pick("").is_err());
    }
}
