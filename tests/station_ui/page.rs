//! Reading the station page's fields. The page replaces live nodes (the
//! pose, the speeds) at every telemetry, so a node found by one WebDriver
//! call may be gone by the next ("stale element"): an attribute or property
//! is read in one script, a text found again if its node went stale.

use std::time::{Duration, Instant};

use fantoccini::{Client, Locator};

/// What `script` returns for the first element `css` matches (bound to
/// `e`), or `null` when none does.
async fn read(c: &Client, css: &str, script: &str, arg: &str) -> serde_json::Value {
    let js = format!("const e = document.querySelector(arguments[0]), a = arguments[1]; return e === null ? null : ({script});");
    c.execute(&js, vec![css.into(), arg.into()])
        .await
        .unwrap_or_else(|err| panic!("{css}: {err}"))
}

/// The attribute `name` of the first element `css` matches, if both exist.
pub async fn attr(c: &Client, css: &str, name: &str) -> Option<String> {
    let v = read(c, css, "e.getAttribute(a)", name).await;
    v.as_str().map(str::to_string)
}

/// The first element `css` matches: its `data-` attribute `name` parsed as JSON.
pub async fn data_of<T: serde::de::DeserializeOwned>(c: &Client, css: &str, name: &str) -> T {
    let v = attr(c, css, name).await.unwrap_or_default();
    serde_json::from_str(&v).unwrap_or_else(|err| panic!("{css} {name}={v:?}: {err}"))
}

/// The text of the element `id`, as WebDriver renders it (visible text,
/// trimmed); found again when the page replaced the node in between.
pub async fn text(c: &Client, id: &str) -> String {
    for _ in 0..100 {
        let e = c.find(Locator::Id(id)).await.unwrap();
        match e.text().await {
            Err(err) if err.is_stale_element_reference() => continue,
            got => return got.unwrap(),
        }
    }
    panic!("#{id} replaced 100 times in a row while being read")
}

/// The element `id`'s exact value (its `data-value`), if it states one.
pub async fn value_of(c: &Client, id: &str) -> Option<f64> {
    let v = attr(c, &format!("#{id}"), "data-value").await;
    v.map(|v| {
        v.parse()
            .unwrap_or_else(|_| panic!("#{id} data-value {v:?}"))
    })
}

/// The property `name` of the element `id` (a form field's value).
pub async fn prop(c: &Client, id: &str, name: &str) -> String {
    let v = read(c, &format!("#{id}"), "e[a]", name).await;
    match v {
        serde_json::Value::Null => String::new(),
        serde_json::Value::String(s) => s,
        v => v.to_string(),
    }
}

/// Wait until `id`'s exact value is `want`.
pub async fn wait_value(c: &Client, id: &str, want: f64) {
    let until = Instant::now() + Duration::from_secs(10 * super::SLACK);
    while value_of(c, id).await != Some(want) {
        assert!(
            Instant::now() < until,
            "#{id} shows {:?}, library {want}",
            value_of(c, id).await
        );
        tokio::time::sleep(Duration::from_millis(100)).await;
    }
}

/// Poll `id`'s text until `ok` holds, for up to `secs` seconds.
pub async fn wait_text(c: &Client, id: &str, secs: u64, ok: impl Fn(&str) -> bool) -> String {
    let until = Instant::now() + Duration::from_secs(secs * super::SLACK);
    loop {
        let t = text(c, id).await;
        if ok(&t) {
            return t;
        }
        assert!(
            Instant::now() < until,
            "#{id} still {t:?} after {} s",
            secs * super::SLACK
        );
        tokio::time::sleep(Duration::from_millis(100)).await;
    }
}
