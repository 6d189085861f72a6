//! Reading the station page's charts from the DOM: each chart is an `<svg>`
//! stating its axes' ranges, scales and labels as data attributes, with its
//! tick labels, legend entries and drawn items as elements.

use std::time::{Duration, Instant};

use fantoccini::elements::Element;
use fantoccini::{Client, Locator};

/// One axis of a chart, as its `<svg>` states it and its tick labels read.
#[derive(Debug)]
pub struct Axis {
    pub min: f64,
    pub max: f64,
    pub px_per_unit: f64,
    pub label: String,
    pub ticks: Vec<f64>,
}

/// What a chart's `<svg>` states of its axis `xy`, read in one script so
/// that a chart redrawn meanwhile (the speeds, at each telemetry) gives one
/// drawing's values.
const AXIS_JS: &str = "
    const svg = document.getElementById(arguments[0]), xy = arguments[1];
    const XY = xy.toUpperCase(), d = svg.dataset;
    const texts = (css) => [...svg.querySelectorAll(css)].map((t) => t.textContent);
    return { min: d[xy + 'Min'], max: d[xy + 'Max'], px: d['pxPer' + XY], label: d[xy + 'Label'],
             shown: texts('text.axis-label.' + xy), ticks: texts('text.tick.' + xy) };";

/// Axis `xy` ("x" or "y") of the chart `id`; its tick labels must be
/// numbers, at least three, increasing, within the range, and its label
/// the one stated.
pub async fn axis(c: &Client, id: &str, xy: &str) -> Axis {
    let v = c
        .execute(AXIS_JS, vec![id.into(), xy.into()])
        .await
        .unwrap();
    let num = |k: &str| -> f64 {
        v[k].as_str()
            .and_then(|s| s.parse().ok())
            .unwrap_or_else(|| panic!("#{id} {xy} {k}: {v}"))
    };
    let ticks = v["ticks"]
        .as_array()
        .unwrap()
        .iter()
        .map(|t| {
            let t = t.as_str().unwrap();
            t.parse()
                .unwrap_or_else(|_| panic!("#{id} {xy} tick {t:?}"))
        })
        .collect();
    let a = Axis {
        min: num("min"),
        max: num("max"),
        px_per_unit: num("px"),
        label: v["label"].as_str().unwrap_or_default().to_string(),
        ticks,
    };
    assert!(a.ticks.len() >= 3, "#{id} {xy}: {a:?}");
    assert!(a.ticks.windows(2).all(|w| w[0] < w[1]), "#{id} {xy}: {a:?}");
    assert!(
        a.min <= a.ticks[0] && *a.ticks.last().unwrap() <= a.max,
        "#{id} {xy}: {a:?}"
    );
    assert_eq!(v["shown"], serde_json::json!([a.label]), "#{id} {xy}");
    a
}

/// The legend entries of the chart `id`.
pub async fn legend(c: &Client, id: &str) -> Vec<String> {
    let js = "return [...document.querySelectorAll('#' + arguments[0] + ' text.legend-item')].map((t) => t.textContent);";
    let v = c.execute(js, vec![id.into()]).await.unwrap();
    serde_json::from_value(v).unwrap()
}

/// A drawn item of a chart: its `data-` attribute `name` parsed as JSON.
pub async fn data<T: serde::de::DeserializeOwned>(e: &Element, name: &str) -> T {
    let v = e.attr(name).await.unwrap().unwrap_or_default();
    serde_json::from_str(&v).unwrap_or_else(|err| panic!("{name}={v:?}: {err}"))
}

/// Wait until `css` matches `n` elements, for up to `secs` seconds.
pub async fn wait_count(c: &Client, css: &str, n: usize, secs: u64) -> Vec<Element> {
    let until = Instant::now() + Duration::from_secs(secs * super::SLACK);
    loop {
        let found = c.find_all(Locator::Css(css)).await.unwrap();
        if found.len() == n {
            return found;
        }
        assert!(
            Instant::now() < until,
            "{css}: {} after {secs} s, not {n}",
            found.len()
        );
        tokio::time::sleep(Duration::from_millis(100)).await;
    }
}

/// Every legend label of every chart that does not fit its legend's box,
/// measured as drawn (the text's computed length in its font); and how many
/// labels were checked.
pub async fn legend_overflow(c: &Client) -> (Vec<String>, usize) {
    let js = "
        const out = []; let n = 0;
        for (const g of document.querySelectorAll('svg.chart g.legend')) {
            const box = g.querySelector('rect');
            const left = Number(box.getAttribute('x'));
            const right = left + Number(box.getAttribute('width'));
            for (const t of g.querySelectorAll('text.legend-item')) {
                n += 1;
                const x = Number(t.getAttribute('x')), end = x + t.getComputedTextLength();
                if (x < left || end > right) {
                    out.push(`${g.closest('svg').id} ${t.textContent}: ${x}..${end} px, box ${left}..${right} px`);
                }
            }
        }
        return [out, n];";
    let v = c.execute(js, vec![]).await.unwrap();
    serde_json::from_value(v).unwrap()
}
