//! Rules symmetric about 0, filled from the nodes of one half.

/// One node of a rule and its weight (on the polished paths the double nearest the root
/// and the weight at the true root).
pub(crate) struct Polished {
    pub(crate) node: f64,
    pub(crate) weight: f64,
}

/// Fills a symmetric rule from the non-negative half of its nodes. `upper(i)` polishes the
/// `i`-th node counted from the right end (`i = 0` is the largest).
pub(crate) fn symmetric(m: usize, upper: impl Fn(usize) -> Polished) -> (Vec<f64>, Vec<f64>) {
    let mut nodes = vec![0.0; m];
    let mut weights = vec![0.0; m];
    for i in 0..m.div_ceil(2) {
        let p = upper(i);
        let (left, right) = (i, m - 1 - i);
        nodes[right] = p.node;
        nodes[left] = -p.node;
        weights[right] = p.weight;
        weights[left] = p.weight;
    }
    (nodes, weights)
}
