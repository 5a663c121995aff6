// The closed card: while the exhibit's opening hours keep it closed (the server's schedule
// message, PROTOCOL.md "schedule") the page dims under a card that says when it opens and
// takes the touches, so nobody dials a sleeping exhibit; in the page's language
// (configs/lang closed.card).
import { t } from './lang.js';

// Shows or hides the card for a schedule message { open, next_change, next_in_s }.
export function showSchedule(m, lang = 'en') {
    let card = document.getElementById('closed');
    if (!card) {
        card = document.createElement('div');
        card.id = 'closed';
        card.className = 'closed';
        card.setAttribute('role', 'status');
        card.hidden = true;
        card.append(document.createElement('div'));
        document.body.append(card);
    }
    // a visitor reads "09:30", not "09:30:00"
    const at = (m.next_change || '').slice(0, 5);
    card.firstChild.textContent = at ? t(lang, 'closed.card', at) : t(lang, 'closed.card_no_time');
    card.hidden = !!m.open;
}
