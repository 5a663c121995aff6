/* Plain-language captions per wind class for the kiosk, in each language (lang.h): what
 * that wind does to trees. Beaufort forces quote the US National Weather Service's land
 * table, hurricane categories the NHC's Saffir-Simpson sentence on trees; the sources
 * are named in configs/lang/en.po. Only trees: the scene's houses stand through any
 * storm, so a caption of roofs torn off would say what the visitor sees is not so. */
#ifndef GALE_CAPTION_H
#define GALE_CAPTION_H

/* The caption of a wind in lang: its hurricane category's when ss_class (wind_scale.h
 * numbering) is a hurricane, else its Beaufort force's (a tropical storm is Beaufort
 * 8-11; forces past 12 read as 12). A static string. */
const char *caption_for(int lang, int ss_class, int beaufort);

#endif
