// Live edits: the change feed (GET /changes as server-sent events) tells the page about every
// committed edit, from any client or the CLI; the page then redraws what the edit changed.
import { getJson } from './api.js';

// Follows the feed from the store's latest transaction; calls onChange(change) for each event.
// EventSource reconnects by itself and resends the last event id, so nothing is missed.
export async function followChanges(onChange, onError) {
  let since = 0;
  try {
    since = (await getJson('/changes?wait=0')).last ?? 0;
  } catch (e) {
    onError(e);
  }
  const source = new EventSource(`/changes?since=${since}`);
  source.addEventListener('change', (event) => {
    try {
      onChange(JSON.parse(event.data));
    } catch (e) {
      onError(e);
    }
  });
  source.onerror = () => onError(new Error('the change feed was interrupted; reconnecting'));
  return source;
}
